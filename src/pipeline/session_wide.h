#pragma once
// The session-wide step of `mocaplabel validate` (docs/validation.md "Session-wide errors"). One
// record's depth cannot tell a 5 mm camera-mount error from the estimate's own error 2.5 m away, but
// every label that camera took carries the same error, so the session's records together can: the
// calibration self-check (calibrate/calibration_check.h) runs over the validation's reliable records,
// and when it finds a camera's mount off, every record of that camera the per-record check accepted
// becomes suspect (`camera_mount_off`), the finding in its reason. An object's mount found off by more
// than the widest per-record accept bounds (at the near end of its 95 % interval) makes every accepted
// record of that object suspect (`object_mount_off`): far from the camera a 1 cm mount error, drawn into
// the label run's masks, cuts a cloud that pulls each estimate towards its label, while the session's
// records still find it. Correct labels give smaller findings, from a surface's depth bias (a table top's
// 2-3 mm); an object declared `tof_range_biased` is left out, since its finding can be the bias of its
// range on a time-of-flight camera (7 mm for the reflective bottle). The latency finding flags no record:
// the per-record check judges what it moves.
#include <string>
#include <vector>

#include "calibrate/calibration_check.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

struct SessionWideOptions {
  bool enabled = true;  ///< `mocaplabel validate --no-session-wide` turns it off
  CalibrationCheckOptions calibration;  ///< the self-check's options (its defaults, as `calibrate check`)
  /// An object mount finding flags its object's records beyond these (the widest per-record accept
  /// bounds, VerdictOptions::accept_position_m and accept_rotation_deg).
  double object_mount_mm = 5.0;
  double object_mount_deg = 3.0;
  void check() const;  ///< throws InputError
};

/// Runs the step over `validation` (records changed in place, summary recomputed and its session_wide
/// filled). Fewer reliable records than the check needs is not an error: the summary says why it did
/// not run. Returns the indices of the records it flagged.
std::vector<size_t> FlagSessionWideErrors(SessionValidation& validation, const std::vector<ValidationObject>& objects,
                                          const SessionWideOptions& options);

/// One line for reports: "camera_mount kinect1 4.90 mm (95 %: +-0.03)", "latency +42.4 ms (95 %: +-4.2)".
std::string FindingText(const CheckFinding& finding);

}  // namespace mocap::pipeline
