#pragma once
// Object mount from depth: where an object's mesh sits on its tracked body (T_objbody_mesh), from the
// SegICP estimates of a validated session.
//
// A label is T_camera_mesh_label = T_camera_objbody * T_objbody_mesh_current (DESIGN.md chain); the
// validator's SegICP estimate from the measured depth is T_camera_mesh_segicp. If the depth is right,
//   T_objbody_mesh = T_objbody_mesh_current * inv(T_camera_mesh_label) * T_camera_mesh_segicp
// per record, without going back to the tracker streams. The per-record estimates are combined robustly:
// records whose estimate lies further than `outlier_sigmas` robust deviations (1.4826 MAD) from the
// median in position or angle are dropped, the rest averaged (translations by mean, rotations by the
// quaternion average of Markley et al., core/rigid3.h). The spread and a 95 % interval of the mean are
// reported; the interval is widened by the lag-1 autocorrelation of consecutive records (an AR(1)
// variance factor (1 + rho) / (1 - rho)) because neighbouring frames see the same view.
#include <span>
#include <string>
#include <vector>

#include "core/rigid3.h"

namespace mocap {

/// One validated record of the object: the label and the independent estimate, both camera frame.
struct LabelEstimatePair {
  Rigid3d T_camera_mesh_label;
  Rigid3d T_camera_mesh_segicp;
};

struct ObjectMountOptions {
  int min_records = 10;          ///< reliable records needed
  double outlier_sigmas = 3.0;   ///< robust deviations from the median beyond which a record is dropped
  double min_outlier_mm = 2.0;   ///< floor of the position outlier bound (noise-free data has MAD 0)
  double min_outlier_deg = 1.0;  ///< floor of the angle outlier bound
  /// Throws InputError naming the field.
  void check() const;
};

struct ObjectMountResult {
  Rigid3d T_objbody_mesh;           ///< the estimate
  Rigid3d correction;               ///< inv(current) * estimate: the change the estimate makes
  int records_used = 0;
  int records_dropped = 0;          ///< outliers
  double spread_mm = 0, spread_deg = 0;  ///< RMS deviation of the records used from the estimate
  double ci95_mm = 0, ci95_deg = 0;      ///< half-width of a 95 % interval of the estimate
  double autocorrelation = 0;            ///< lag-1, of the per-record position deviations
  std::vector<std::string> warnings;
};

/// The mount estimate from `pairs` (in recording order). Throws InputError for invalid options and
/// "too few records: N reliable (need K)" when fewer than min_records pairs remain after the outliers.
ObjectMountResult EstimateObjectMount(std::span<const LabelEstimatePair> pairs, const Rigid3d& T_objbody_mesh_current,
                                      const ObjectMountOptions& options = {});

/// Robust location of poses: the per-pose position and angle deviations from a first average, the
/// poses within `sigmas` robust deviations (with the floors) kept. Returns the indices kept.
std::vector<int> InlierPoses(std::span<const Rigid3d> poses, double sigmas, double min_mm, double min_deg);

}  // namespace mocap
