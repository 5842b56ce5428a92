#include "pipeline/session_wide.h"

#include <algorithm>
#include <cstdio>
#include <set>

#include "core/check.h"
#include "pipeline/calibration_records.h"

namespace mocap::pipeline {
namespace {

std::string Fixed(double v, int decimals) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

/// Why the finding makes this record's label wrong, for its reason line.
std::string FlagReason(const CheckFinding& f, size_t records_used, const std::string& own_reason) {
  return Str("the session's ", records_used, " reliable records together find ", FindingText(f),
             " off; every label of this camera carries it (this record alone: ", own_reason, ")");
}

}  // namespace

std::string FindingText(const CheckFinding& f) {
  if (f.kind == CheckItemKind::kLatency)
    return Str("latency ", f.latency_error_ms >= 0 ? "+" : "", Fixed(f.latency_error_ms, 1), " ms (95 %: +-",
               Fixed(f.latency_ci95_ms, 1), ")");
  // A finding reports the parts it estimated: a translation, a rotation or both (zero intervals: not fitted).
  std::string size;
  if (f.ci95_mm > 0) size = Str(Fixed(f.size_mm, 1), " mm (95 %: +-", Fixed(f.ci95_mm, 2), ")");
  if (f.ci95_deg > 0) size += Str(size.empty() ? "" : " and ", Fixed(f.size_deg, 2), " deg (95 %: +-", Fixed(f.ci95_deg, 2), ")");
  return Str(ToString(f.kind), " ", f.name, " ", size);
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
    std::set<std::string> cameras_off;
    for (const CheckFinding& f : result.findings) {
      summary.findings.push_back(FindingText(f));
      if (f.kind == CheckItemKind::kCameraMount) cameras_off.insert(f.name);
    }
    for (size_t i = 0; i < validation.records.size(); ++i) {
      RecordCheck& r = validation.records[i];
      if (r.check.verdict != Verdict::kAccept || !cameras_off.contains(r.camera)) continue;
      const auto finding = std::find_if(result.findings.begin(), result.findings.end(), [&](const CheckFinding& f) {
        return f.kind == CheckItemKind::kCameraMount && f.name == r.camera;
      });
      r.check.verdict = Verdict::kSuspect;
      r.check.reason_code = VerdictReason::kCameraMountOff;
      r.check.reason = FlagReason(*finding, records.size(), r.check.reason);
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
