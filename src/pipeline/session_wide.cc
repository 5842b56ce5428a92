#include "pipeline/session_wide.h"

#include <cstdio>
#include <map>

#include "core/check.h"
#include "pipeline/calibration_records.h"

namespace mocap::pipeline {
namespace {

/// Why the finding makes this record's label wrong, for its reason line.
std::string FlagReason(const CheckFinding& f, size_t records_used, const std::string& own_reason) {
  return Str("the session's ", records_used, " reliable records together find ", FindingText(f),
             " off; every label of this camera carries it (this record alone: ", own_reason, ")");
}

}  // namespace

std::string FindingText(const CheckFinding& f) {
  if (f.kind == CheckItemKind::kLatency) {
    char text[64];
    std::snprintf(text, sizeof text, "latency %+.1f ms (95 %%: +-%.1f)", f.latency_error_ms, f.latency_ci95_ms);
    return text;
  }
  return Str(ToString(f.kind), " ", f.name, " ", MountSizeText(f));
}

std::vector<size_t> FlagSessionWideErrors(SessionValidation& validation, const std::vector<ValidationObject>& objects,
                                          const SessionWideOptions& options) {
  SessionWideSummary summary;
  std::vector<size_t> flagged;
  const std::vector<CheckRecord> records = CalibrationCheckRecords(validation.records, objects);
  if (static_cast<int>(records.size()) < options.calibration.min_records) {
    summary.why_not = Str(records.size(), " records with a reliable estimate; the session-wide check needs ",
                          options.calibration.min_records);
  } else {
    const CalibrationCheckResult result = CheckCalibration(records, options.calibration);
    summary.ran = true;
    std::map<std::string, const CheckFinding*> camera_off;
    for (const CheckFinding& f : result.findings) {
      summary.findings.push_back(FindingText(f));
      if (f.kind == CheckItemKind::kCameraMount) camera_off[f.name] = &f;
    }
    for (size_t i = 0; i < validation.records.size(); ++i) {
      RecordCheck& r = validation.records[i];
      const auto finding = camera_off.find(r.camera);
      if (r.check.verdict != Verdict::kAccept || finding == camera_off.end()) continue;
      r.check.verdict = Verdict::kSuspect;
      r.check.reason_code = VerdictReason::kCameraMountOff;
      r.check.reason = FlagReason(*finding->second, records.size(), r.check.reason);
      flagged.push_back(i);
    }
    summary.records_flagged = static_cast<int64_t>(flagged.size());
  }
  const double seconds = validation.summary.seconds;
  const std::string nothing_checked_why = validation.summary.nothing_checked_why;
  validation.summary = Summarise(validation.records, validation.summary.records);
  validation.summary.seconds = seconds;
  validation.summary.nothing_checked_why = nothing_checked_why;  // flags change verdicts, not what was checked
  validation.summary.session_wide = summary;
  return flagged;
}

}  // namespace mocap::pipeline
