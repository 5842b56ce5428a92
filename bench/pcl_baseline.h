#pragma once
// The PCL baseline of the validator benchmark: pcl::IterativeClosestPoint on the same clouds. PCL types
// stay inside pcl_baseline.cc (one translation unit: PCL headers compile slowly).
#include <memory>

#include "core/rigid3.h"
#include "validate/point_cloud.h"

namespace mocap::bench {

struct PclIcpSettings {
  double max_correspondence_distance_m = 0.05;
  int max_iterations = 20;
  double transformation_epsilon = 1e-8;
};

/// A scene cloud with its FLANN kd-tree built once (setSearchMethodTarget(tree, true)), as a fair PCL
/// user would.
class PclScene {
 public:
  explicit PclScene(const PointCloud& scene);
  ~PclScene();
  /// pcl::IterativeClosestPoint from T_scene_source_init; returns the final transform.
  Rigid3d Align(const PointCloud& source, const Rigid3d& T_scene_source_init, const PclIcpSettings& settings) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mocap::bench
