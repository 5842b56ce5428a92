// The renderer's projection against cv::projectPoints (DESIGN.md: well under 0.1 px): small discs facing
// the camera are rasterised at known 3D positions across the whole image, corners included, and the
// centroid of each rendered silhouette is compared with cv::projectPoints of the disc centre.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>
#include <opencv2/calib3d.hpp>

#include "render/primitives.h"
#include "render/renderer.h"

namespace mocap {
namespace {

PinholeCamera Kinect1Like(bool distorted) {
  PinholeCamera cam{640, 480, 525.3, 524.8, 319.6, 239.2, {}};
  if (distorted) cam.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  return cam;
}

constexpr int kRimVertices = 64;

struct Marker {
  Eigen::Vector3d center_camera;
  double radius_m = 0;
  Eigen::Vector2d expected_px;  ///< area centroid of the disc's rim projected by cv::projectPoints
};

/// Area centroid of a closed polygon (shoelace formula).
Eigen::Vector2d PolygonCentroid(const std::vector<cv::Point2d>& p) {
  double area = 0, cx = 0, cy = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const cv::Point2d& a = p[i];
    const cv::Point2d& b = p[(i + 1) % p.size()];
    const double cross = a.x * b.y - b.x * a.y;
    area += cross, cx += (a.x + b.x) * cross, cy += (a.y + b.y) * cross;
  }
  return {cx / (3 * area), cy / (3 * area)};
}

/// Discs of `radius_px` facing the camera whose centres lie on a 7x5 grid spanning the image, the outer
/// ones `inset_px` from the border, at depths between 0.6 and 2.0 m. The expected position is computed
/// from cv::projectPoints of the disc's rim vertices (the rendered polygon), so the curvature of the
/// distortion across the disc does not bias the comparison.
std::vector<Marker> MakeMarkers(const PinholeCamera& cam, double radius_px, double inset_px) {
  const cv::Matx33d K(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1);
  const std::vector<double> dist(cam.dist.begin(), cam.dist.end());
  std::vector<Marker> markers;
  for (int j = 0; j < 5; ++j) {
    for (int i = 0; i < 7; ++i) {
      const double u = inset_px + (cam.width - 1 - 2 * inset_px) * i / 6.0;
      const double v = inset_px + (cam.height - 1 - 2 * inset_px) * j / 4.0;
      const double z = 0.6 + 1.4 * ((i + 2 * j) % 5) / 4.0;
      Marker m{cam.Unproject({u, v}, z), radius_px * z / cam.fx, {}};
      std::vector<cv::Point3d> rim;
      for (int k = 0; k < kRimVertices; ++k) {
        const double a = 2 * 3.141592653589793 * k / kRimVertices;
        rim.emplace_back(m.center_camera.x() + m.radius_m * std::cos(a), m.center_camera.y() + m.radius_m * std::sin(a), z);
      }
      std::vector<cv::Point2d> projected;
      cv::projectPoints(rim, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, projected);
      m.expected_px = PolygonCentroid(projected);
      markers.push_back(m);
    }
  }
  return markers;
}

/// Mean pixel distance between the rendered silhouette centroids and cv::projectPoints.
double MeanCentroidError(const PinholeCamera& cam, double radius_px, double* max_error) {
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  const auto markers = MakeMarkers(cam, radius_px, radius_px * 1.3 + 2);
  std::vector<RenderItem> items;
  for (size_t k = 0; k < markers.size(); ++k) {
    // Facing the camera (identity rotation).
    items.push_back({renderer.Upload(MakeDiscMesh(markers[k].radius_m, kRimVertices)),
                     Rigid3d(Eigen::Quaterniond::Identity(), markers[k].center_camera), static_cast<uint16_t>(k + 1)});
  }
  const RenderOutput out = renderer.Render(cam, items);
  double sum = 0;
  *max_error = 0;
  for (size_t k = 0; k < markers.size(); ++k) {
    const ObjectLayer& layer = out.layers[k];
    Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
    int n = 0;
    for (int v = layer.rect.y; v < layer.rect.y + layer.rect.height; ++v)
      for (int u = layer.rect.x; u < layer.rect.x + layer.rect.width; ++u)
        if (layer.depth_at(u, v) > 0) centroid += Eigen::Vector2d(u, v), ++n;
    EXPECT_GT(n, 0.8 * 3.14159 * radius_px * radius_px) << "marker " << k << " mostly visible";
    centroid /= std::max(n, 1);
    const double error = (centroid - markers[k].expected_px).norm();
    sum += error;

    *max_error = std::max(*max_error, error);
  }
  return sum / markers.size();
}

TEST(Projection, PinholeMatchesProjectPoints) {
  double max_error = 0;
  const double mean = MeanCentroidError(Kinect1Like(false), 10.0, &max_error);
  RecordProperty("mean_px", std::to_string(mean));
  EXPECT_LT(mean, 0.05) << "max " << max_error;
  EXPECT_LT(max_error, 0.15);
}

TEST(Projection, Kinect1DistortionMatchesProjectPoints) {
  double max_error = 0;
  const double mean = MeanCentroidError(Kinect1Like(true), 10.0, &max_error);
  RecordProperty("mean_px", std::to_string(mean));
  EXPECT_LT(mean, 0.2) << "max " << max_error;
  EXPECT_LT(max_error, 0.5);
}

TEST(Projection, AmodalBoxIncludesPartsOutsideTheImage) {
  // A 40.5 px square centred on the image's left border at u = 0 (edges off pixel centres, so the
  // coverage is 41 x 41 pixel centres): columns -20..20 and rows 220..260; half lies outside.
  const PinholeCamera cam = Kinect1Like(false);
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  const double z = 1.0, side_m = 40.5 * z / cam.fx;
  const Eigen::Vector3d center = cam.Unproject({0.0, 240.0}, z);
  const RenderItem item{renderer.Upload(MakeRectangleMesh(side_m, 40.5 * z / cam.fy)),
                        Rigid3d(Eigen::Quaterniond::Identity(), center), 7};
  const RenderOutput out = renderer.Render(cam, std::span(&item, 1));
  const ObjectLayer& layer = out.layers[0];
  EXPECT_EQ(layer.bbox_obj[0], -20);
  EXPECT_EQ(layer.bbox_obj[1], 220);
  EXPECT_EQ(layer.bbox_obj[2], 40) << "BOP's w = x_max - x_min";
  EXPECT_EQ(layer.bbox_obj[3], 40);
  EXPECT_EQ(layer.px_count_all, 41 * 41);
  int inside = 0;
  for (uint16_t id : out.instance_ids.data) inside += id == 7;
  EXPECT_EQ(inside, 21 * 41);
  EXPECT_FALSE(layer.truncated_by_canvas);
}

TEST(Projection, DistortedAmodalBoxExtendsOutsideTheImage) {
  // Through the Kinect v1 distortion, a square straddling the left border: its outside part is located
  // through the distortion model, so bbox_obj starts left of the image and px_count_all exceeds the
  // pixels inside.
  const PinholeCamera cam = Kinect1Like(true);
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  const double z = 1.0;
  const Eigen::Vector3d center = cam.Unproject({0.0, 240.0}, z);
  const RenderItem item{renderer.Upload(MakeRectangleMesh(40.5 * z / cam.fx, 40.5 * z / cam.fy)),
                        Rigid3d(Eigen::Quaterniond::Identity(), center), 5};
  const RenderOutput out = renderer.Render(cam, std::span(&item, 1));
  int inside = 0;
  for (uint16_t id : out.instance_ids.data) inside += id == 5;
  const ObjectLayer& layer = out.layers[0];
  EXPECT_GT(inside, 0);
  EXPECT_LT(layer.bbox_obj[0], -10);
  EXPECT_GT(layer.px_count_all, inside + 300);
  // The image centre of the square is at u = 0 by construction; its amodal box straddles it.
  EXPECT_NEAR(layer.bbox_obj[0] + layer.bbox_obj[2] / 2.0, 0.0, 3.0);
}

TEST(Projection, OneContextPerThreadRendersTheSame) {
  // The documented threading model: independent contexts on different threads, identical results.
  const PinholeCamera cam = Kinect1Like(false);
  auto render_in_thread = [&](LabelImage& ids) {
    const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
    Renderer renderer(*context);
    const MeshHandle sphere = renderer.Upload(MakeSphereMesh(0.08, 4000));
    const std::vector<RenderItem> items = {{sphere, Rigid3d::FromRvec({0, 0, 0}, {0.0, 0.0, 0.8}), 1},
                                           {sphere, Rigid3d::FromRvec({0, 0, 0}, {0.1, 0.05, 1.0}), 2}};
    for (int i = 0; i < 5; ++i) ids = renderer.Render(cam, items).instance_ids;
  };
  LabelImage a, b;
  std::thread ta(render_in_thread, std::ref(a)), tb(render_in_thread, std::ref(b));
  ta.join();
  tb.join();
  ASSERT_EQ(a.data.size(), b.data.size());
  EXPECT_EQ(a.data, b.data);
  EXPECT_GT(std::count(a.data.begin(), a.data.end(), uint16_t{2}), 100);
}

}  // namespace
}  // namespace mocap
