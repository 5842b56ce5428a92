#include "core/camera.h"

#include <gtest/gtest.h>

#include "core/check.h"

#include <opencv2/calib3d.hpp>
#include <random>
#include <vector>

namespace mocap {
namespace {

PinholeCamera Kinect1Like(bool distorted) {
  PinholeCamera cam{.width = 640, .height = 480, .fx = 517.3, .fy = 516.5, .cx = 318.6, .cy = 255.3};
  if (distorted) cam.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  return cam;
}

// Points that land all over the image, corners included.
std::vector<Eigen::Vector3d> GridPoints(const PinholeCamera& cam) {
  std::vector<Eigen::Vector3d> points;
  for (double u : {0.0, 0.5 * cam.width, cam.width - 1.0})
    for (double v : {0.0, 0.5 * cam.height, cam.height - 1.0})
      for (double z : {0.5, 1.7, 4.0}) points.push_back(cam.Unproject({u, v}, z));
  return points;
}

void ExpectMatchesOpenCv(const PinholeCamera& cam, double tolerance_px) {
  const auto points = GridPoints(cam);
  std::vector<cv::Point3d> object;
  for (const auto& p : points) object.emplace_back(p.x(), p.y(), p.z());
  cv::Mat K = (cv::Mat_<double>(3, 3) << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  std::vector<double> dist(cam.dist.begin(), cam.dist.end());
  std::vector<cv::Point2d> expected;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, expected);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto px = cam.Project(points[i]);
    ASSERT_TRUE(px.has_value());
    EXPECT_NEAR(px->x(), expected[i].x, tolerance_px);
    EXPECT_NEAR(px->y(), expected[i].y, tolerance_px);
  }
}

TEST(PinholeCamera, ProjectionMatchesCvProjectPoints) {
  ExpectMatchesOpenCv(Kinect1Like(false), 1e-9);
  ExpectMatchesOpenCv(Kinect1Like(true), 1e-9);
  PinholeCamera rational = Kinect1Like(false);
  rational.dist = {0.1, -0.05, 0.001, -0.002, 0.01, 0.05, -0.01, 0.002};  // 8-coefficient rational model
  ExpectMatchesOpenCv(rational, 1e-9);
}

TEST(PinholeCamera, UnprojectInvertsProject) {
  const PinholeCamera cam = Kinect1Like(true);
  for (const auto& p : GridPoints(cam)) {
    const auto px = cam.Project(p);
    ASSERT_TRUE(px);
    const Eigen::Vector3d back = cam.Unproject(*px, p.z());
    EXPECT_LT((back - p).norm(), 1e-9);
  }
}

TEST(PinholeCamera, BehindTheCameraDoesNotProject) {
  EXPECT_FALSE(Kinect1Like(false).Project({0, 0, -1}).has_value());
  EXPECT_FALSE(Kinect1Like(false).Project({0, 0, 0}).has_value());
}

TEST(PinholeCamera, DepthToPointsSkipsInvalidPixels) {
  // PCL's organised-cloud convention for Kinect: fx = fy = 525, cx = 320, cy = 240.
  const PinholeCamera cam{.width = 4, .height = 3, .fx = 525, .fy = 525, .cx = 320, .cy = 240};
  DepthImage depth(4, 3, 0.0f);
  depth.at(1, 2) = 2.0f;
  depth.at(3, 0) = 1.0f;
  std::vector<Eigen::Vector2i> pixels;
  const auto points = DepthToPoints(depth, cam, &pixels);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(pixels[0], Eigen::Vector2i(3, 0));
  EXPECT_NEAR(points[0].x(), (3 - 320.0) / 525.0, 1e-12);
  EXPECT_NEAR(points[1].y(), (2 - 240.0) / 525.0 * 2.0, 1e-12);
  LabelImage mask(4, 3, 0);
  mask.at(1, 2) = 7;
  EXPECT_EQ(DepthToPointsMasked(depth, cam, mask, 7).size(), 1u);
  EXPECT_TRUE(DepthToPointsMasked(depth, cam, mask, 8).empty());
}

// The back-projections compute a pinhole camera's rays per row and column; they must give exactly what
// Unproject gives pixel by pixel, with and without distortion.
TEST(PinholeCamera, DepthToPointsMaskedMatchesUnprojectExactly) {
  for (const bool distorted : {false, true}) {
    const PinholeCamera cam = Kinect1Like(distorted);
    DepthImage depth(cam.width, cam.height, 0.0f);
    LabelImage mask(cam.width, cam.height, 0);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> z(0.4f, 4.0f);
    std::vector<Eigen::Vector3d> expected;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u) {
        depth.at(u, v) = (u + v) % 5 == 0 ? 0.0f : z(rng);
        mask.at(u, v) = (u * 7 + v * 3) % 4 == 0 ? 2 : 1;
        if (mask.at(u, v) == 2 && depth.at(u, v) > 0) expected.push_back(cam.Unproject({u, v}, depth.at(u, v)));
      }
    const std::vector<Eigen::Vector3d> points = DepthToPointsMasked(depth, cam, mask, 2);
    ASSERT_EQ(points.size(), expected.size());
    for (size_t i = 0; i < points.size(); ++i) ASSERT_EQ(points[i], expected[i]) << "point " << i << " distorted " << distorted;
    // The unmasked back-projection shares the rays.
    std::vector<Eigen::Vector3d> every;
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u)
        if (depth.at(u, v) > 0) every.push_back(cam.Unproject({u, v}, depth.at(u, v)));
    EXPECT_EQ(DepthToPoints(depth, cam), every) << "distorted " << distorted;
  }
}

TEST(PinholeCamera, CheckRejectsNonsense) {
  PinholeCamera cam;
  EXPECT_THROW(cam.check(), InputError);
  cam = Kinect1Like(false);
  EXPECT_NO_THROW(cam.check());
  cam.fx = -1;
  EXPECT_THROW(cam.check(), InputError);
}

}  // namespace
}  // namespace mocap
