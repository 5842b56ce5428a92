#include "pcl_baseline.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/search/kdtree.h>

namespace mocap::bench {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr ToPcl(const PointCloud& points) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                                              static_cast<float>(p.z())));
  return cloud;
}

}  // namespace

struct PclScene::Impl {
  pcl::PointCloud<pcl::PointXYZ>::Ptr scene;
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree;
};

PclScene::PclScene(const PointCloud& scene) : impl_(std::make_unique<Impl>()) {
  impl_->scene = ToPcl(scene);
  impl_->tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  impl_->tree->setInputCloud(impl_->scene);
}

PclScene::~PclScene() = default;

Rigid3d PclScene::Align(const PointCloud& source, const Rigid3d& T_scene_source_init,
                        const PclIcpSettings& settings) const {
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  icp.setInputSource(ToPcl(source));
  icp.setInputTarget(impl_->scene);
  icp.setSearchMethodTarget(impl_->tree, true);
  icp.setMaxCorrespondenceDistance(settings.max_correspondence_distance_m);
  icp.setMaximumIterations(settings.max_iterations);
  icp.setTransformationEpsilon(settings.transformation_epsilon);
  pcl::PointCloud<pcl::PointXYZ> aligned;
  icp.align(aligned, T_scene_source_init.matrix4().cast<float>());
  Eigen::Matrix4d T = icp.getFinalTransformation().cast<double>();
  // Re-orthonormalise the float rotation before handing it to Rigid3d.
  const Eigen::Quaterniond q(Eigen::Matrix3d(T.topLeftCorner<3, 3>()));
  return Rigid3d(q.normalized(), T.topRightCorner<3, 1>());
}

}  // namespace mocap::bench
