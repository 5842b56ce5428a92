// Open3D's ICP behind the validator's Registration interface (registration_backends.h). Open3D types stay in
// this translation unit.
#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>

#include <cmath>

#include "registration_backends.h"
#include "scene_index_cache.h"

namespace mocap::bench {
namespace {

namespace o3d = open3d;
using o3d::pipelines::registration::ICPConvergenceCriteria;
using o3d::pipelines::registration::RegistrationResult;
using o3d::pipelines::registration::TransformationEstimation;

struct Open3dScene {
  o3d::geometry::PointCloud cloud;
  o3d::geometry::KDTreeFlann tree;
};

/// The scene's cloud and kd-tree; with `normal_radius_m` > 0 also its normals (EstimateNormals, hybrid
/// search of at most 30 neighbours, turned towards the camera at the origin).
std::shared_ptr<const Open3dScene> BuildScene(const PointGrid& grid, double normal_radius_m) {
  auto scene = std::make_shared<Open3dScene>();
  scene->cloud.points_.reserve(grid.size());
  for (size_t i = 0; i < grid.size(); ++i) scene->cloud.points_.push_back(grid.point(i));
  if (normal_radius_m > 0) {
    scene->cloud.EstimateNormals(o3d::geometry::KDTreeSearchParamHybrid(normal_radius_m, 30));
    scene->cloud.OrientNormalsTowardsCameraLocation(Eigen::Vector3d::Zero());
  }
  scene->tree.SetGeometry(scene->cloud);
  return scene;
}

/// Open3D's GetRegistrationResultAndCorrespondences, against the scene's tree built once.
RegistrationResult Correspond(const o3d::geometry::PointCloud& source, const Open3dScene& scene, double gate_m,
                              const Eigen::Matrix4d& T) {
  RegistrationResult result(T);
  std::vector<int> index(1);
  std::vector<double> distance_sq(1);
  double error_sq = 0.0;
  for (int i = 0; i < static_cast<int>(source.points_.size()); ++i) {
    if (scene.tree.SearchHybrid(source.points_[i], gate_m, 1, index, distance_sq) > 0) {
      error_sq += distance_sq[0];
      result.correspondence_set_.push_back(Eigen::Vector2i(i, index[0]));
    }
  }
  if (!result.correspondence_set_.empty()) {
    const double n = static_cast<double>(result.correspondence_set_.size());
    result.fitness_ = n / static_cast<double>(source.points_.size());
    result.inlier_rmse_ = std::sqrt(error_sq / n);
  }
  return result;
}

/// Open3D's RegistrationICP loop (0.16) with the tree built once per scene: transform the source by the
/// initial guess, then estimate, apply and re-correspond until fitness and RMSE stop changing.
IcpResult Icp(o3d::geometry::PointCloud source, const Open3dScene& scene, double gate_m, const Rigid3d& T_init,
              const TransformationEstimation& estimation, int max_iterations) {
  const ICPConvergenceCriteria criteria(1e-6, 1e-6, max_iterations);
  Eigen::Matrix4d T = T_init.matrix4();
  source.Transform(T);
  RegistrationResult result = Correspond(source, scene, gate_m, T);
  IcpResult out;
  out.reason = IcpStopReason::kMaxIterations;
  for (int i = 0; i < criteria.max_iteration_; ++i) {
    const Eigen::Matrix4d update = estimation.ComputeTransformation(source, scene.cloud, result.correspondence_set_);
    T = update * T;
    source.Transform(update);
    const RegistrationResult last = result;
    result = Correspond(source, scene, gate_m, T);
    ++out.iterations;
    if (std::abs(last.fitness_ - result.fitness_) < criteria.relative_fitness_ &&
        std::abs(last.inlier_rmse_ - result.inlier_rmse_) < criteria.relative_rmse_) {
      out.converged = true;
      out.reason = IcpStopReason::kConverged;
      break;
    }
  }
  out.T_target_source = RigidFromMatrix(T);
  out.inlier_rmse_m = result.inlier_rmse_;
  out.fitness = result.fitness_;
  out.num_inliers = static_cast<int>(result.correspondence_set_.size());
  return out;
}

class Open3dRegistration final : public Registration {
 public:
  std::string_view name() const override { return "open3d"; }

  IcpResult PointToPoint(const PointCloud& source_model, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                         const IcpOptions& options) const override {
    if (source_model.empty() || scene_camera.size() == 0) return UnmovedResult(T_camera_model_init);
    const auto scene = points_.Get(scene_camera, [](const PointGrid& g) { return BuildScene(g, 0.0); });
    o3d::geometry::PointCloud source;
    source.points_ = source_model;
    return Icp(std::move(source), *scene, options.initial_correspondence_distance_m, T_camera_model_init,
               o3d::pipelines::registration::TransformationEstimationPointToPoint(false), options.max_iterations);
  }

  IcpResult PointToPlane(const ModelCrop& crop, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                         const ObservabilityOptions& options, double first_gate_m,
                         PlaneRefinement* /*refinement: the validator's own only*/) const override {
    if (crop.points_model.empty() || scene_camera.size() == 0) return UnmovedResult(T_camera_model_init);
    const double radius_m = options.normal_radius_m;
    const auto scene = with_normals_.Get(scene_camera, [radius_m](const PointGrid& g) { return BuildScene(g, radius_m); });
    o3d::geometry::PointCloud source;
    const size_t stride = PointToPlaneStride(crop.points_model.size(), options.max_points);
    for (size_t i = 0; i < crop.points_model.size(); i += stride) source.points_.push_back(crop.points_model[i]);
    return Icp(std::move(source), *scene, std::max(first_gate_m, options.support_distance_m), T_camera_model_init,
               o3d::pipelines::registration::TransformationEstimationPointToPlane(), options.refine_iterations);
  }

 private:

  SceneIndexCache<Open3dScene> points_;
  SceneIndexCache<Open3dScene> with_normals_;
};

}  // namespace

std::shared_ptr<const Registration> MakeOpen3dRegistration() { return std::make_shared<Open3dRegistration>(); }

}  // namespace mocap::bench
