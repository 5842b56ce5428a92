// ColorAlignedDepthM: BOP and TUM assume depth aligned with the colour image (formats.md §1, §6), which
// a Kinect v2 does not deliver (its 512x424 depth camera sits beside the 1920x1080 colour camera). The
// warp is core's RegisterDepthToColor, the one the validator uses.
#include <algorithm>
#include <opencv2/core.hpp>

#include "core/depth_registration.h"
#include "exporters/dataset/dataset.h"

namespace mocap::exporters {
namespace {

cv::Mat ToMat(const DepthImage& depth_m) {
  cv::Mat out(depth_m.height, depth_m.width, CV_32FC1);
  std::copy(depth_m.data.begin(), depth_m.data.end(), out.ptr<float>());
  return out;
}

}  // namespace

cv::Mat ColorAlignedDepthM(const ExportScene& scene, const ExportFrame& frame) {
  if (frame.depth_path.empty()) return {};
  const DepthImage depth_m = scene.session->LoadDepth(scene.camera, frame.index);
  if (scene.depth_registered_to_color) return ToMat(depth_m);
  return ToMat(RegisterDepthToColor(depth_m, scene.depth_camera, scene.color_camera, scene.T_color_depth));
}

}  // namespace mocap::exporters
