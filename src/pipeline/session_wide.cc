#include "pipeline/session_wide.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "core/check.h"
#include "pipeline/calibration_records.h"

namespace mocap::pipeline {
namespace {

/// Why the finding makes this record's label wrong, for its reason line.
std::string FlagReason(const CheckFinding& f, size_t records_used, const std::string& own_reason) {
  return Str("the session's ", records_used, " reliable records together find ", FindingText(f), " off; every label of this ",
             f.kind == CheckItemKind::kCameraMount ? "camera" : "object", " carries it (this record alone: ", own_reason, ")");
}

/// An object mount finding beyond the widest per-record bounds, even at the near end of its interval.
bool FlagsItsObject(const CheckFinding& f, const std::vector<ValidationObject>& objects, const SessionWideOptions& options) {
  if (f.kind != CheckItemKind::kObjectMount) return false;
  const auto object = std::find_if(objects.begin(), objects.end(), [&](const ValidationObject& o) { return o.name == f.name; });
  if (object == objects.end() || object->tof_range_biased) return false;
  return f.size_mm - f.ci95_mm > options.object_mount_mm || f.size_deg - f.ci95_deg > options.object_mount_deg;
}

}  // namespace

void SessionWideOptions::check() const {
  calibration.check();
  if (!(object_mount_mm > 0) || !(object_mount_deg > 0))
    throw InputError("session_wide", "object_mount_mm and object_mount_deg must be positive");
}

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
  options.check();
  SessionWideSummary summary;
  std::vector<size_t> flagged;
  const std::vector<CheckRecord> records = CalibrationCheckRecords(validation.records, objects);
  if (static_cast<int>(records.size()) < options.calibration.min_records) {
    summary.why_not = Str(records.size(), " records with a reliable estimate; the session-wide check needs ",
                          options.calibration.min_records);
  } else {
    const CalibrationCheckResult result = CheckCalibration(records, options.calibration);
    summary.ran = true;
    std::map<std::string, const CheckFinding*> camera_off, object_off;
    for (const CheckFinding& f : result.findings) {
      summary.findings.push_back(FindingText(f));
      if (f.kind == CheckItemKind::kCameraMount) camera_off[f.name] = &f;
      if (FlagsItsObject(f, objects, options)) object_off[f.name] = &f;
    }
    for (size_t i = 0; i < validation.records.size(); ++i) {
      RecordCheck& r = validation.records[i];
      if (r.check.verdict != Verdict::kAccept) continue;
      // The camera's finding first: a camera mount error also shows as object mount findings.
      const auto camera = camera_off.find(r.camera);
      const auto object = object_off.find(r.name);
      const CheckFinding* finding = camera != camera_off.end() ? camera->second
                                    : object != object_off.end() ? object->second
                                                                 : nullptr;
      if (!finding) continue;
      r.check.verdict = Verdict::kSuspect;
      r.check.reason_code = finding->kind == CheckItemKind::kCameraMount ? VerdictReason::kCameraMountOff
                                                                          : VerdictReason::kObjectMountOff;
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
