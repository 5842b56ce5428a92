#pragma once
// Fixtures shared by the session tests: a fresh temporary folder and a two-camera, two-tracker manifest.
#include <unistd.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <random>
#include <string>

#include "session/manifest.h"

namespace mocap::testing {

/// A new empty folder under the system temp dir, removed when the object goes.
class TempDir {
 public:
  TempDir() {
    std::random_device random;
    path_ = std::filesystem::temp_directory_path() /
            ("mocap_session_test_" + std::to_string(::getpid()) + "_" + std::to_string(random()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline PinholeCamera Kinect1Intrinsics() {
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = 517.3;
  camera.fy = 516.5;
  camera.cx = 318.6;
  camera.cy = 255.3;
  camera.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  return camera;
}

/// kinect1 (mm depth, carried by body "cam") and tum (depth 1/5000 m) cameras; an NDI tracker with
/// bodies "cam" and "obj", and a BOP-style tracker of known object poses in the tum camera.
inline SessionManifest TwoCameraManifest() {
  SessionManifest manifest;
  manifest.software_version = "test";
  manifest.source = "test";
  CameraStreamInfo kinect;
  kinect.name = "kinect1";
  kinect.model = "kinect1";
  kinect.serial = "A00362A10251047A";
  kinect.color_camera = Kinect1Intrinsics();
  kinect.depth_camera = Kinect1Intrinsics();
  kinect.depth_unit_m = 0.001;
  kinect.camera_body = "cam";
  kinect.T_body_camera = Rigid3d::FromRvec({0.1, -0.2, 0.3}, {0.01, 0.02, -0.05});
  CameraStreamInfo tum = kinect;
  tum.name = "tum";
  tum.model = "tum";
  tum.serial = "";
  tum.depth_unit_m = 1.0 / 5000.0;
  tum.camera_body = "";
  tum.T_body_camera = Rigid3d::Identity();
  tum.depth_registered_to_color = false;
  tum.T_color_depth = Rigid3d::FromRvec({0.0, 0.01, 0.0}, {0.025, 0.0, 0.0});
  manifest.cameras = {kinect, tum};
  TrackerStreamInfo ndi{"ndi", "polaris_vega", "P9-01234", "tracker", {"cam", "obj"}};
  TrackerStreamInfo known{"known", "bop", "", "camera:tum", {"obj_000001"}};
  manifest.trackers = {ndi, known};
  manifest.extra = {{"rig", "calib/lab.yaml"}, {"nested", {{"a", 1}}}};
  return manifest;
}

/// A 640x480 colour image with texture (so PNG has something to compress) seeded by `seed`.
inline cv::Mat TestColor(int seed, int width = 640, int height = 480) {
  cv::Mat color(height, width, CV_8UC3);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      color.at<cv::Vec3b>(v, u) = cv::Vec3b(static_cast<uint8_t>(u + seed), static_cast<uint8_t>(v * 3 + seed),
                                            static_cast<uint8_t>((u ^ v) + seed));
  return color;
}

/// A 16-bit depth image (units), a slanted plane with a hole of zeros, seeded by `seed`.
inline cv::Mat TestDepth(int seed, int width = 640, int height = 480) {
  cv::Mat depth(height, width, CV_16UC1);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      depth.at<uint16_t>(v, u) = (u > 100 && u < 140 && v > 50 && v < 90) ? 0 : static_cast<uint16_t>(800 + u + 2 * v + seed);
  return depth;
}

}  // namespace mocap::testing
