#pragma once
// The session-wide step of `mocaplabel validate` (docs/validation.md "Session-wide errors"). One
// record's depth cannot tell a 5 mm camera-mount error from the estimate's own error 2.5 m away, but
// every label that camera took carries the same error, so the session's records together can: the
// calibration self-check (calibrate/calibration_check.h) runs over the validation's reliable records,
// and when it finds a camera's mount off, every record of that camera the per-record check accepted
// becomes suspect (`camera_mount_off`), the finding in its reason. The check's other findings (an object
// mount, the latency) are reported in the summary but flag no record: the per-record check judges those
// errors itself, and an object-mount finding also appears with correct labels where the depth of a
// surface is biased (a reflective object on a time-of-flight camera).
#include <string>
#include <vector>

#include "calibrate/calibration_check.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

struct SessionWideOptions {
  bool enabled = true;  ///< `mocaplabel validate --no-session-wide` turns it off
  CalibrationCheckOptions calibration;  ///< the self-check's options (its defaults, as `calibrate check`)
  void check() const { calibration.check(); }  ///< throws InputError
};

/// Runs the step over `validation` (records changed in place, summary recomputed and its session_wide
/// filled). Fewer reliable records than the check needs is not an error: the summary says why it did
/// not run. Returns the indices of the records it flagged.
std::vector<size_t> FlagSessionWideErrors(SessionValidation& validation, const std::vector<ValidationObject>& objects,
                                          const SessionWideOptions& options);

/// One line for reports: "camera_mount kinect1 4.90 mm (95 %: +-0.03)", "latency +42.4 ms (95 %: +-4.2)".
std::string FindingText(const CheckFinding& finding);

}  // namespace mocap::pipeline
