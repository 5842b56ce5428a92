// A Kinect v2's depth registered into the colour image (session/depth_in_color.h, core/depth_registration.h)
// and the combined visibility rule on it: the registration leaves a hole beside a nearer surface (the
// baseline's occlusion shadow: colour pixels the depth camera cannot see), which the hole rule must keep
// on the object behind, while the near surface itself hides it. Drawn one character per pixel.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/check.h"
#include "picture.h"
#include "session/depth_in_color.h"
#include "label/object_labels.h"

namespace mocap {
namespace {

using test::Lines;
using test::Picture;

constexpr float kObject_m = 1.0f, kHand_m = 0.7f;
constexpr int kWidth = 30, kHeight = 4;

/// The colour camera: fx 200 px. The depth camera sits 5 cm to its left (x = -0.05 m in the colour
/// frame), with its principal point 10 px further left, so that a surface at 1 m lands on the same
/// column in both and a nearer one shifts left by 10 px * (1 / z - 1) in the colour image.
PinholeCamera ColorCamera() { return {kWidth, kHeight, 200.0, 200.0, 14.5, 1.5, {}}; }
PinholeCamera DepthCamera() { return {kWidth, kHeight, 200.0, 200.0, 4.5, 1.5, {}}; }
Rigid3d TColorDepth() { return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.05, 0, 0)); }

/// 'o' the object at 1 m, 'h' an unmodelled hand at 0.7 m, '_' no depth.
DepthImage DepthOf(const Picture& p) {
  DepthImage d(static_cast<int>(p[0].size()), static_cast<int>(p.size()), 0.0f);
  for (int v = 0; v < d.height; ++v)
    for (int u = 0; u < d.width; ++u) d.at(u, v) = p[v][u] == 'o' ? kObject_m : p[v][u] == 'h' ? kHand_m : 0.0f;
  return d;
}

Picture Draw(const DepthImage& d) {
  Picture p(static_cast<size_t>(d.height), std::string(static_cast<size_t>(d.width), '?'));
  for (int v = 0; v < d.height; ++v)
    for (int u = 0; u < d.width; ++u) {
      const float z = d.at(u, v);
      p[v][u] = z == 0.0f ? '_' : std::abs(z - kObject_m) < 1e-4f ? 'o' : std::abs(z - kHand_m) < 1e-4f ? 'h' : '?';
    }
  return p;
}

/// The object alone rendered in the colour camera: a wall at 1 m over the whole image.
RenderOutput WallRender() {
  RenderOutput r{LabelImage(kWidth, kHeight, 1), DepthImage(kWidth, kHeight, kObject_m), {}};
  ObjectLayer layer{1, {0, 0, kWidth, kHeight}, std::vector<float>(size_t{kWidth} * kHeight, kObject_m)};
  layer.px_count_all = kWidth * kHeight;
  r.layers.push_back(std::move(layer));
  return r;
}

DepthInColor Kinect2Like() {
  CameraStreamInfo info;
  info.depth_registered_to_color = false;
  info.depth_camera = DepthCamera();
  info.color_camera = ColorCamera();
  info.T_color_depth = TColorDepth();
  return DepthInColor::Of(info, ColorCamera());
}

// The depth camera sees the hand over its columns 12-17 and the object elsewhere.
const Picture kDepthCameraView = {
    "oooooooooooohhhhhhoooooooooooo",
    "oooooooooooohhhhhhoooooooooooo",
    "oooooooooooohhhhhhoooooooooooo",
    "oooooooooooohhhhhhoooooooooooo",
};

TEST(DepthInColor, RegistrationLeavesTheBaselinesShadowAsAHole) {
  // In colour the hand moves 4.3 px left (it covers 7.2-13.2); the object behind the hand's old place,
  // colour columns 14-17, was hidden from the depth camera: no depth there.
  const Picture expected = {
      "ooooooohhhhhhh____oooooooooooo",
      "ooooooohhhhhhh____oooooooooooo",
      "ooooooohhhhhhh____oooooooooooo",
      "ooooooohhhhhhh____oooooooooooo",
  };
  EXPECT_EQ(Lines(Draw(Kinect2Like().ToColor(DepthOf(kDepthCameraView)))), Lines(expected));
}

TEST(DepthInColor, TheShadowStaysOnTheObjectAndTheHandHidesIt) {
  const DepthImage registered = Kinect2Like().ToColor(DepthOf(kDepthCameraView));
  const RenderOutput render = WallRender();
  VisibilityOptions options;  // a 5 cm shadow baseline: 200 px * 0.05 m * (1/0.7 - 1) = 4.3 px
  const ObjectLabels wall = ComputeObjectLabels(render, ColorCamera(), &registered, options).at(0);
  // Truly visible: columns 0-6 and 14-29. The hole's column next to the hand (14) goes to the hand, as
  // the rule gives every occluder its edge pixel; 15-17 lie within the shadow's width: the object.
  const std::string row = "#######........###############";
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u)
      EXPECT_EQ(wall.masks.at(wall.masks.visible_measured, u, v), row[u] == '#') << "pixel " << u << ", " << v;
  EXPECT_EQ(wall.stats.px_count_visib_assumed, 3 * kHeight);  // the shadow's pixels rest on the rule
}

TEST(DepthInColor, RegisteredDepthPassesThroughAndWrongSizesAreRefused) {
  CameraStreamInfo info;
  info.depth_registered_to_color = true;
  info.color_camera = info.depth_camera = ColorCamera();
  const DepthInColor registered = DepthInColor::Of(info, ColorCamera());
  const DepthImage depth = DepthOf(kDepthCameraView);
  EXPECT_EQ(Lines(Draw(registered.ToColor(depth))), Lines(kDepthCameraView));
  EXPECT_THROW(registered.ToColor(DepthImage(kWidth + 1, kHeight, 1.0f)), InputError);
  EXPECT_THROW(Kinect2Like().ToColor(DepthImage(kWidth, kHeight + 1, 1.0f)), InputError);
}

TEST(DepthInColor, TheRigsTColorDepthReplacesTheManifests) {
  CameraStreamInfo info;
  info.depth_registered_to_color = false;
  info.T_color_depth = TColorDepth();
  const Rigid3d fixed(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.052, 0, 0));
  EXPECT_EQ(DepthInColor::Of(info, ColorCamera()).T_color_depth.translation(), TColorDepth().translation());
  EXPECT_EQ(DepthInColor::Of(info, ColorCamera(), fixed).T_color_depth.translation(), fixed.translation());
}

}  // namespace
}  // namespace mocap
