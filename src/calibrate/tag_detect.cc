#include "calibrate/tag_detect.h"

#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

#include "calibrate/board.h"
#include "core/check.h"

namespace mocap {
namespace {

constexpr int kSamplesPerEdge = 40;
constexpr double kEdgeStart = 0.2, kEdgeEnd = 0.8;  // skip the corners, where the markers sit
constexpr double kMinStepGrey = 8;                  // weakest dark-to-light step taken as the border
constexpr size_t kMinEdgePoints = 12;

double Bilinear(const cv::Mat& gray, const Eigen::Vector2d& p) {
  const int x = static_cast<int>(std::floor(p.x())), y = static_cast<int>(std::floor(p.y()));
  const double ax = p.x() - x, ay = p.y() - y;
  const auto at = [&](int yy, int xx) { return static_cast<double>(gray.at<uint8_t>(yy, xx)); };
  return (1 - ay) * ((1 - ax) * at(y, x) + ax * at(y, x + 1)) + ay * ((1 - ax) * at(y + 1, x) + ax * at(y + 1, x + 1));
}

bool Inside(const cv::Mat& gray, const Eigen::Vector2d& p, double margin) {
  return p.x() >= margin && p.y() >= margin && p.x() < gray.cols - 1 - margin && p.y() < gray.rows - 1 - margin;
}

Eigen::Vector2d PixelOf(const PinholeCamera& camera, const Eigen::Vector2d& xy) {
  return *camera.Project({xy.x(), xy.y(), 1.0});
}

// Offset along `outward` (pixels) of the steepest dark-to-light step within +-half_width, sub-pixel by a
// parabola through the three best samples; empty when the step is weak or at the window's end.
std::optional<double> EdgeOffset(const cv::Mat& gray, const Eigen::Vector2d& p, const Eigen::Vector2d& outward,
                                 double half_width) {
  if (!Inside(gray, p, half_width + 2)) return std::nullopt;
  constexpr double kStep = 0.25;
  const int n = static_cast<int>(half_width / kStep);
  std::vector<double> slope;
  for (int i = -n; i <= n; ++i)
    slope.push_back(Bilinear(gray, p + outward * (i * kStep + 0.5)) - Bilinear(gray, p + outward * (i * kStep - 0.5)));
  const size_t best = static_cast<size_t>(std::max_element(slope.begin(), slope.end()) - slope.begin());
  if (best == 0 || best + 1 == slope.size() || slope[best] < kMinStepGrey) return std::nullopt;
  const double denominator = slope[best - 1] - 2 * slope[best] + slope[best + 1];
  const double vertex = denominator < 0 ? 0.5 * (slope[best - 1] - slope[best + 1]) / denominator : 0.0;
  return (static_cast<double>(best) - n + vertex) * kStep;
}

struct EdgeLine {
  Eigen::Vector3d line;  // a x + b y + c = 0 in normalised coordinates, (a, b) unit
  double rms_px = 0;
  size_t points = 0;
};

Eigen::Vector3d FitLine(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::Vector2d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(scatter).eigenvectors().col(0);
  return {normal.x(), normal.y(), -normal.dot(mean)};
}

// Total least squares, then once more without the points beyond 3x the median distance.
std::optional<EdgeLine> RobustLine(std::vector<Eigen::Vector2d> points, double fx) {
  if (points.size() < kMinEdgePoints) return std::nullopt;
  Eigen::Vector3d line = FitLine(points);
  std::vector<double> distance;
  for (const auto& p : points) distance.push_back(std::abs(line.dot(p.homogeneous())));
  std::vector<double> sorted = distance;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
  const double limit = std::max(3 * sorted[sorted.size() / 2], 0.1 / fx);
  std::vector<Eigen::Vector2d> kept;
  for (size_t i = 0; i < points.size(); ++i)
    if (distance[i] <= limit) kept.push_back(points[i]);
  if (kept.size() < kMinEdgePoints) return std::nullopt;
  EdgeLine edge{FitLine(kept), 0, kept.size()};
  for (const auto& p : kept) edge.rms_px += std::pow(edge.line.dot(p.homogeneous()) * fx, 2);
  edge.rms_px = std::sqrt(edge.rms_px / static_cast<double>(kept.size()));
  return edge;
}

// The edge from corner a to corner b: sampled on the straight segment in normalised coordinates (so the
// samples follow the edge's curved image), searched across it in the image.
std::optional<EdgeLine> FitEdge(const cv::Mat& gray, const PinholeCamera& camera, const Eigen::Vector2d& a_px,
                                const Eigen::Vector2d& b_px, const Eigen::Vector2d& centre_px, double half_width) {
  const Eigen::Vector2d a = camera.Ray(a_px).head<2>(), b = camera.Ray(b_px).head<2>();
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < kSamplesPerEdge; ++i) {
    const double t = kEdgeStart + (kEdgeEnd - kEdgeStart) * i / (kSamplesPerEdge - 1);
    const Eigen::Vector2d p = PixelOf(camera, a + t * (b - a));
    const Eigen::Vector2d along = (PixelOf(camera, a + (t + 0.01) * (b - a)) - p).normalized();
    Eigen::Vector2d outward(-along.y(), along.x());
    if (outward.dot(p - centre_px) < 0) outward = -outward;
    const std::optional<double> offset = EdgeOffset(gray, p, outward, half_width);
    if (offset) points.push_back(camera.Ray(p + *offset * outward).head<2>());
  }
  return RobustLine(std::move(points), camera.fx);
}

cv::Mat GrayOf(const cv::Mat& image, const PinholeCamera& camera) {
  if (image.empty()) throw InputError("DetectTags", "the image is empty");
  if (image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    throw InputError("DetectTags", Str("need an 8-bit grey or BGR image, got type ", image.type()));
  if (image.cols != camera.width || image.rows != camera.height)
    throw InputError("DetectTags", Str("the image is ", image.cols, "x", image.rows, " but the camera is ",
                                       camera.width, "x", camera.height));
  if (image.channels() == 1) return image;
  cv::Mat gray;
  cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

}  // namespace

void RefineTagCorners(const cv::Mat& gray, const PinholeCamera& camera, TagDetection& tag) {
  for (int pass = 0; pass < 3; ++pass) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& c : tag.corners_px) centre += c / 4;
    std::array<EdgeLine, 4> edges;
    for (size_t k = 0; k < 4; ++k) {
      const auto edge = FitEdge(gray, camera, tag.corners_px[k], tag.corners_px[(k + 1) % 4], centre, pass ? 3 : 8);
      if (!edge) return;  // keep the corners of the last complete pass
      edges[k] = *edge;
    }
    tag.edge_rms_px = 0;
    for (size_t k = 0; k < 4; ++k) {
      const Eigen::Vector3d corner = edges[(k + 3) % 4].line.cross(edges[k].line);  // edge into k, edge out of k
      tag.corners_px[k] = PixelOf(camera, corner.hnormalized());
      tag.edge_rms_px += edges[k].rms_px * edges[k].rms_px / 4;
    }
    tag.edge_rms_px = std::sqrt(tag.edge_rms_px);
    tag.refined = true;
  }
}

std::vector<TagDetection> DetectTags(const cv::Mat& image, std::string_view dictionary, const PinholeCamera& camera) {
  camera.check();
  const cv::Mat gray = GrayOf(image, camera);
  const cv::Ptr<cv::aruco::Dictionary> dict = cv::aruco::getPredefinedDictionary(ArucoDictionaryId(dictionary));
  const cv::Ptr<cv::aruco::DetectorParameters> parameters = cv::aruco::DetectorParameters::create();
  // Contour refinement (lines through the thresholded border) starts the edge search within a few pixels.
  parameters->cornerRefinementMethod = cv::aruco::CORNER_REFINE_CONTOUR;
  std::vector<std::vector<cv::Point2f>> corners;
  std::vector<int> ids;
  cv::aruco::detectMarkers(gray, dict, corners, ids, parameters);
  std::vector<TagDetection> tags(ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    tags[i].id = ids[i];
    for (size_t k = 0; k < 4; ++k) tags[i].corners_px[k] = {corners[i][k].x, corners[i][k].y};
    RefineTagCorners(gray, camera, tags[i]);
  }
  std::sort(tags.begin(), tags.end(), [](const TagDetection& a, const TagDetection& b) { return a.id < b.id; });
  return tags;
}

}  // namespace mocap
