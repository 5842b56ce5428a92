// PCL's ICP behind the validator's Registration interface (registration_backends.h). PCL types stay in this
// translation unit (PCL headers compile slowly).
#include <pcl/features/normal_3d.h>
#include <pcl/filters/filter.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/search/kdtree.h>

#include <cmath>

#include "registration_backends.h"
#include "scene_index_cache.h"

namespace mocap::bench {
namespace {

template <typename Point>
struct PclScene {
  typename pcl::PointCloud<Point>::Ptr cloud;
  typename pcl::search::KdTree<Point>::Ptr tree;
};

/// Exposes the iteration count PCL keeps protected.
template <typename Icp>
struct CountingIcp : Icp {
  int iterations() const { return this->nr_iterations_; }
};

pcl::PointCloud<pcl::PointXYZ>::Ptr ToXyz(const PointGrid& grid) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(grid.size());
  for (size_t i = 0; i < grid.size(); ++i) {
    const Eigen::Vector3f p = grid.point(i).cast<float>();
    cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  }
  return cloud;
}

template <typename Point>
typename pcl::search::KdTree<Point>::Ptr TreeOf(const typename pcl::PointCloud<Point>::Ptr& cloud) {
  auto tree = pcl::make_shared<pcl::search::KdTree<Point>>();
  tree->setInputCloud(cloud);
  return tree;
}

std::shared_ptr<const PclScene<pcl::PointXYZ>> BuildPoints(const PointGrid& grid) {
  auto scene = std::make_shared<PclScene<pcl::PointXYZ>>();
  scene->cloud = ToXyz(grid);
  scene->tree = TreeOf<pcl::PointXYZ>(scene->cloud);
  return scene;
}

/// The scene with normals (pcl::NormalEstimation over `radius_m`, turned towards the camera at the origin);
/// points whose neighbourhood gives no normal are dropped, as PointToPlaneLLS cannot use them.
std::shared_ptr<const PclScene<pcl::PointNormal>> BuildWithNormals(const PointGrid& grid, double radius_m) {
  const auto xyz = ToXyz(grid);
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(xyz);
  estimation.setSearchMethod(TreeOf<pcl::PointXYZ>(xyz));
  estimation.setRadiusSearch(radius_m);
  estimation.setViewPoint(0.0f, 0.0f, 0.0f);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  auto with_normals = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  pcl::concatenateFields(*xyz, normals, *with_normals);
  auto scene = std::make_shared<PclScene<pcl::PointNormal>>();
  scene->cloud = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  pcl::Indices kept;
  pcl::removeNaNNormalsFromPointCloud(*with_normals, *scene->cloud, kept);
  scene->tree = TreeOf<pcl::PointNormal>(scene->cloud);
  return scene;
}

/// Runs a configured PCL ICP (in double precision: a rotation threshold of a few thousandths of a degree
/// lies below float's resolution of the rotation's cosine) from T_init and reads back what it found.
template <typename Icp>
IcpResult Run(Icp& icp, const Rigid3d& T_init, double gate_m) {
  typename Icp::PointCloudSource aligned;
  icp.align(aligned, T_init.matrix4().cast<typename Icp::Matrix4::Scalar>());
  IcpResult result;
  result.T_target_source = RigidFromMatrix(icp.getFinalTransformation().template cast<double>());
  result.iterations = icp.iterations();
  result.converged = icp.hasConverged();
  result.reason = result.converged ? IcpStopReason::kConverged : IcpStopReason::kMaxIterations;
  // The acquisition breaks ties by the inlier RMSE: PCL's fitness score is the mean squared distance of
  // the source points with a scene point within the gate.
  result.inlier_rmse_m = std::sqrt(icp.getFitnessScore(gate_m));
  return result;
}

class PclRegistration final : public Registration {
 public:
  std::string_view name() const override { return "pcl"; }

  IcpResult PointToPoint(const PointCloud& source_model, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                         const IcpOptions& options) const override {
    if (source_model.empty() || scene_camera.size() == 0) return UnmovedResult(T_camera_model_init);
    const auto scene = points_.Get(scene_camera, BuildPoints);
    auto source = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
    source->reserve(source_model.size());
    for (const Eigen::Vector3d& p : source_model)
      source->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())));
    CountingIcp<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ, double>> icp;
    icp.setInputSource(source);
    icp.setInputTarget(scene->cloud);
    icp.setSearchMethodTarget(scene->tree, true);
    Configure(icp, options.initial_correspondence_distance_m, options.max_iterations, options.translation_epsilon_m,
              options.rotation_epsilon_deg);
    return Run(icp, T_camera_model_init, options.initial_correspondence_distance_m);
  }

  IcpResult PointToPlane(const ModelCrop& crop, const PointGrid& scene_camera, const Rigid3d& T_camera_model_init,
                         const ObservabilityOptions& options, double first_gate_m,
                         PlaneRefinement* /*refinement: the validator's own only*/) const override {
    if (crop.points_model.empty() || scene_camera.size() == 0) return UnmovedResult(T_camera_model_init);
    const double radius_m = options.normal_radius_m;
    const auto scene = with_normals_.Get(scene_camera, [radius_m](const PointGrid& g) { return BuildWithNormals(g, radius_m); });
    if (scene->cloud->size() < 3) return UnmovedResult(T_camera_model_init);
    auto source = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
    const bool has_normals = crop.normals_model.size() == crop.points_model.size();
    const size_t stride = PointToPlaneStride(crop.points_model.size(), options.max_points);
    for (size_t i = 0; i < crop.points_model.size(); i += stride) {
      pcl::PointNormal p;
      p.getVector3fMap() = crop.points_model[i].cast<float>();
      p.getNormalVector3fMap() = has_normals ? Eigen::Vector3f(crop.normals_model[i].cast<float>()) : Eigen::Vector3f::Zero();
      source->push_back(p);
    }
    CountingIcp<pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal, double>> icp;
    icp.setInputSource(source);
    icp.setInputTarget(scene->cloud);
    icp.setSearchMethodTarget(scene->tree, true);
    const double gate_m = std::max(first_gate_m, options.support_distance_m);
    // The validator's own stops when a step moves less than refine_step_m, in rotation as an arc at the
    // crop's radius (taken here as a typical 5 cm).
    Configure(icp, gate_m, options.refine_iterations, options.refine_step_m, DegFromRad(options.refine_step_m / 0.05));
    return Run(icp, T_camera_model_init, gate_m);
  }

 private:
  template <typename Icp>
  static void Configure(Icp& icp, double gate_m, int max_iterations, double translation_epsilon_m, double rotation_epsilon_deg) {
    icp.setMaxCorrespondenceDistance(gate_m);
    icp.setMaximumIterations(max_iterations);
    icp.setTransformationEpsilon(translation_epsilon_m * translation_epsilon_m);  // PCL compares the squared norm
    icp.setTransformationRotationEpsilon(std::cos(RadFromDeg(rotation_epsilon_deg)));
  }

  SceneIndexCache<PclScene<pcl::PointXYZ>> points_;
  SceneIndexCache<PclScene<pcl::PointNormal>> with_normals_;
};

}  // namespace

std::shared_ptr<const Registration> MakePclRegistration() { return std::make_shared<PclRegistration>(); }

}  // namespace mocap::bench
