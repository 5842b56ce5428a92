#pragma once
// Helpers for session-level validation tests: sessions with measured depth built from real BOP data,
// label runs made with mount errors, and the rates the checks are judged by. They take any session + label folder,
// so a simulated Kinect session (`mocaplabel sim record`, then `mocaplabel label`) plugs in the same way.
#include <filesystem>
#include <string>
#include <vector>

#include "core/rigid3.h"
#include "sim/scenario.h"
#include "validate/session_check.h"

namespace mocap::testing {

/// A fresh, empty folder under the system temp directory.
std::filesystem::path FreshTempDir(const std::string& name);

/// The objects of a session's objects.yaml (what `mocaplabel validate` reads by default).
std::vector<ValidationObject> SessionObjects(const std::filesystem::path& session_dir);

/// LM-O scene 2 (../shared/realdata/bop_lmo_scene2) has ground-truth poses and real meshes but no depth
/// images. This builds, under `dir`:
///   L   the label run of the imported scene (instance PNGs, rendered depth, overlays),
///   S   a session of the same frames whose depth is the label run's rendered depth of all objects with
///       Kinect1 axial noise (sigma 1.425e-3 z^2 m) and 1 mm quantisation (the BOP depth_scale).
/// Frames listed in `frames_without_depth` (stream indices) get no depth image.
struct BopDepthScene {
  std::filesystem::path session, labels;
  std::vector<ValidationObject> objects;
};
BopDepthScene MakeBopDepthScene(const std::filesystem::path& dir, const std::vector<int64_t>& frames_without_depth,
                                uint32_t seed);

/// Every object's mount off by `translation_m` and `angle_deg`, each in its own random direction (drawn
/// from `seed`, in the order of `objects`): the errors a labeller is given, so that the label run's
/// masks are drawn at the wrong labels, as a user's wrong mount calibration draws them.
sim::CalibrationErrors ObjectMountErrors(const std::vector<std::string>& objects, double translation_m, double angle_deg,
                                         uint32_t seed);

/// MakeBopDepthScene's label run (`dir` as made there) drawn again by the labeller, into `dir`/L_`name`,
/// with the mount errors of ObjectMountErrors (composed on the body side, T_body_mesh * error, as
/// sim::ApplyCalibrationErrors does). The outline estimate reads the masks as the model's silhouette at the label (validate/outline.h),
/// so a mount error whose masks stay the correct labels' is not what a user's session holds.
std::filesystem::path LabelWithMountErrors(const std::filesystem::path& dir, const std::string& name,
                                           double translation_m, double angle_deg, uint32_t seed);

/// Fractions over the records whose input was usable (an estimate was attempted).
struct Rates {
  int64_t checked = 0;
  double accepted = 0.0;  ///< verdict accept
  double flagged = 0.0;   ///< verdict suspect or reject
  double success = 0.0;   ///< the paper's criterion
};
Rates ComputeRates(const SessionValidation& validation);

}  // namespace mocap::testing
