#pragma once
// The estimate of an object whose measured range is pushed back by multipath (a reflective surface seen
// by a time-of-flight camera: objects.yaml `tof_range_biased`), fitted together with that push.
//
// Multipath adds path length, and more of it where the surface turns away from the camera: the SegICP
// paper's oil bottle on the Kinect v2 (§V) came back deformed, not just farther. A rigid fit of a deformed
// surface turns as well as shifts: on a hand-held Kinect v2 the bottle's point-to-plane estimate turned
// 2-4 deg about its upright axis. Here the depth is modelled as the model's surface moved along each
// ray u of the time-of-flight camera by push_m (1 - cos theta), theta the incidence angle on that ray:
// nothing where the surface faces the camera, push_m at grazing incidence. The rays are the depth
// camera's, not those of the colour camera the check is in: a Kinect v2's depth camera sits 5 cm beside
// it, a few degrees' difference at a metre, and a fit along the colour camera's rays left the hand-held
// bottle 2 deg turned. That is the form the simulated rig uses (sim/kinect2_model.h), a
// first-order model of the deformation's growth with incidence, not one fitted to a real sensor. The
// point-to-plane residual of model point p (normal n, camera frame) becomes n.(T p + push (1 - cos theta) u - s):
// the normal equations gain one column, g = (1 - cos theta) n.u. The push is eliminated (Schur complement)
// and the pose steps along every direction with information left. The push trades off against the pose
// (its mean part against the range, its spread against turns), so those directions keep little
// information: a threshold as RefinePointToPlane's (observability.h min_information) would leave the pose
// where the rigid fit put it along exactly them.
#include "core/rigid3.h"
#include "validate/model_crop.h"
#include "validate/observability.h"
#include "validate/point_grid.h"

namespace mocap {

struct RangePushOptions {
  /// The pose steps along directions of the eliminated equations with at least this information per point.
  double min_information = 1e-3;
  /// Correspondence gate, metres: the push reaches 2-3 cm at grazing incidence.
  double gate_m = 0.02;
  int iterations = 20;
  /// Stop once a step moves the pose (translation, and rotation as an arc at the crop's radius) and the
  /// push by less than this, metres.
  double stop_m = 1e-5;
  void check() const;  ///< throws InputError naming the field
};

struct RangePushFit {
  Rigid3d T_camera_object;
  double push_m = 0.0;  ///< the push at grazing incidence (positive: the range measured too long)
  int iterations = 0;
  bool converged = false;
};

/// Gauss-Newton from `T_camera_object_init` over `crop`'s points (every k-th, keeping at most
/// observability.max_points) matched within options.gate_m, with observability.robust_sigmas' kernel.
/// `tof_center_camera`: the depth camera's centre in the check's camera frame (T_color_depth's translation).
RangePushFit FitWithRangePush(const ModelCrop& crop, const Rigid3d& T_camera_object_init, const PointGrid& scene_camera,
                              const Eigen::Vector3d& tof_center_camera, const RangePushOptions& options,
                              const ObservabilityOptions& observability);

}  // namespace mocap
