#include "validate/registration.h"

namespace mocap {
namespace {

/// A point-to-plane refinement as a registration result (the refinement counts no inliers and has no stop
/// reason of its own; those fields keep their defaults).
IcpResult ToIcpResult(const PlaneRefinement& refined) {
  IcpResult result;
  result.T_target_source = refined.T_camera_object;
  result.iterations = refined.iterations;
  result.inlier_rmse_m = refined.rmse_m;
  result.converged = refined.iterations > 0;
  return result;
}

}  // namespace

IcpResult SegIcpRegistration::PointToPoint(const PointCloud& source_model, const PointGrid& scene_camera,
                                           const Rigid3d& T_camera_model_init, const IcpOptions& options) const {
  return AlignPointToPoint(source_model, scene_camera, T_camera_model_init, options);
}

IcpResult SegIcpRegistration::PointToPlane(const ModelCrop& crop, const PointGrid& scene_camera,
                                           const Rigid3d& T_camera_model_init, const ObservabilityOptions& options,
                                           double first_gate_m, PlaneRefinement* refinement) const {
  PlaneRefinement refined = RefinePointToPlane(crop, T_camera_model_init, scene_camera, options, first_gate_m);
  const IcpResult result = ToIcpResult(refined);
  if (refinement) *refinement = std::move(refined);
  return result;
}

const Registration& RegistrationOrOwn(const std::shared_ptr<const Registration>& registration) {
  static const SegIcpRegistration own;
  return registration ? *registration : own;
}

}  // namespace mocap
