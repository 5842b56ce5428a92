#pragma once
// Other libraries' ICP behind the validator's Registration interface (validate/registration.h), so that
// bench_validate_session runs the same pipeline with PCL's or Open3D's registration in place of ours.
// Each is set up as a fair user of that library would: the scene's kd-tree (and, for point-to-plane, its
// normals) built once per scene (SceneIndexCache), the same source points, correspondence distance,
// iterations and, as far as the library expresses them, convergence thresholds as ours:
//  - point-to-point: the gate is IcpOptions' initial (widest) distance, fixed, as neither library shrinks
//    its gate; at most max_iterations;
//  - point-to-plane (the tracking step): every k-th crop point as ours (ObservabilityOptions::max_points),
//    the scene's normals estimated over normal_radius_m and turned to the camera, the gate first_gate_m,
//    at most refine_iterations iterations. Ours moves only in the observable directions; theirs in all six.
#include <algorithm>
#include <cmath>
#include <memory>

#include "core/rigid3.h"
#include "validate/registration.h"

namespace mocap::bench {

/// pcl::IterativeClosestPoint (point-to-point) and pcl::IterativeClosestPointWithNormals (point-to-plane:
/// TransformationEstimationPointToPlaneLLS against the scene's normals from pcl::NormalEstimation).
/// Convergence: setTransformationEpsilon(translation_epsilon_m^2) and
/// setTransformationRotationEpsilon(cos(rotation_epsilon_deg)). Null when built without PCL.
std::shared_ptr<const Registration> MakePclRegistration();

/// Open3D's RegistrationICP loop with TransformationEstimationPointToPoint / PointToPlane (target normals
/// from PointCloud::EstimateNormals), run against a KDTreeFlann built once per scene: RegistrationICP
/// itself builds a tree on every call. Convergence: Open3D's ICPConvergenceCriteria (relative fitness
/// and RMSE change below 1e-6; it has no pose-change test). Null when built without Open3D.
std::shared_ptr<const Registration> MakeOpen3dRegistration();

/// Every k-th index of n, k keeping at most max_points (the rule of the validator's point-to-plane step).
inline size_t PointToPlaneStride(size_t n, int max_points) {
  return std::max<size_t>(1, (n + static_cast<size_t>(max_points) - 1) / static_cast<size_t>(max_points));
}

/// The result of a registration that could not run (no source or scene points): the start, unmoved.
inline IcpResult UnmovedResult(const Rigid3d& T_init) {
  IcpResult r;
  r.T_target_source = T_init;
  return r;
}

/// A float-precision 4x4 rigid transform back to Rigid3d, its rotation re-orthonormalised.
inline Rigid3d RigidFromMatrix(const Eigen::Matrix4d& T) {
  const Eigen::Quaterniond q(Eigen::Matrix3d(T.topLeftCorner<3, 3>()));
  return Rigid3d(q.normalized(), T.topRightCorner<3, 1>());
}

}  // namespace mocap::bench
