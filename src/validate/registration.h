#pragma once
// The registrations of the validator behind one interface, so that the same pipeline can run with another
// library's ICP in their place (bench/bench_validate_session.cc runs PCL's and Open3D's on the user's path).
// Two calls go through it: the acquisition's point-to-point ICP (coarse and fine stages) and the tracking
// step's point-to-plane step. The point-to-plane polish of a label check and the observability analysis
// stay the validator's own for every backend: they are the verdict's input, not the registration.
#include <memory>
#include <string_view>

#include "core/rigid3.h"
#include "validate/icp.h"
#include "validate/model_crop.h"
#include "validate/observability.h"
#include "validate/point_cloud.h"
#include "validate/point_grid.h"

namespace mocap {

class Registration {
 public:
  virtual ~Registration() = default;
  /// For reports ("segicp", "pcl", "open3d").
  virtual std::string_view name() const = 0;

  /// Registers `source_model` (model frame) to the scene that `scene_camera` indexes (camera frame),
  /// starting from T_camera_model_init, with the gates, iterations and convergence thresholds of `options`
  /// as far as the backend can express them. Called from several threads at once, on the same scene too.
  virtual IcpResult PointToPoint(const PointCloud& source_model, const PointGrid& scene_camera,
                                 const Rigid3d& T_camera_model_init, const IcpOptions& options) const = 0;

  /// The tracking step: point-to-plane from the prediction T_camera_model_init, the first correspondence
  /// gate `first_gate_m`, then options.support_distance_m, at most options.refine_iterations iterations on
  /// at most options.max_points crop points. Thread-safe as above. `refinement` (may be null): the
  /// validator's own writes its RefinePointToPlane there, whose last equations a label check of the frame
  /// takes as its analysis (TrackStep::refinement); another library's leaves it alone.
  virtual IcpResult PointToPlane(const ModelCrop& crop, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                                 const ObservabilityOptions& options, double first_gate_m,
                                 PlaneRefinement* refinement) const = 0;
};

/// The validator's own: AlignPointToPoint, and RefinePointToPlane, which moves the pose only in the
/// directions the depth constrains.
class SegIcpRegistration final : public Registration {
 public:
  std::string_view name() const override { return "segicp"; }
  IcpResult PointToPoint(const PointCloud& source_model, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                         const IcpOptions& options) const override;
  IcpResult PointToPlane(const ModelCrop& crop, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                         const ObservabilityOptions& options, double first_gate_m,
                         PlaneRefinement* refinement) const override;
};

/// `registration`, or the validator's own when it is null.
const Registration& RegistrationOrOwn(const std::shared_ptr<const Registration>& registration);

}  // namespace mocap
