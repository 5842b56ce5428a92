#include "calibrate/depth_to_color.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "calibrate/robust_stats.h"
#include "core/check.h"

namespace mocap {

void PlaneFitOptions::check() const {
  if (!(inlier_m > 0)) throw InputError("PlaneFitOptions.inlier_m", "must be positive");
  if (iterations < 1) throw InputError("PlaneFitOptions.iterations", "must be >= 1");
  if (min_points < 3) throw InputError("PlaneFitOptions.min_points", "must be >= 3");
}

void DepthToColorOptions::check() const {
  if (min_views < 3) throw InputError("DepthToColorOptions.min_views", "must be >= 3");
  if (!(min_normal_spread_deg >= 0)) throw InputError("DepthToColorOptions.min_normal_spread_deg", "must be >= 0");
}

namespace {

/// The plane through three points facing the origin; nullopt when they are (nearly) on one line.
std::optional<Plane> PlaneThrough(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  if (n.norm() < 1e-12) return std::nullopt;
  Plane p{n.normalized(), n.normalized().dot(a)};
  if (p.offset_m < 0) p.normal = -p.normal, p.offset_m = -p.offset_m;
  return p;
}

double Distance(const Plane& plane, const Eigen::Vector3d& p) { return std::abs(plane.normal.dot(p) - plane.offset_m); }

/// Least-squares plane of `points` (the smallest principal axis through their centroid), facing the origin.
Plane LeastSquaresPlane(const std::vector<Eigen::Vector3d>& points) {
  const PrincipalAxes principal = PrincipalAxesOf(points);
  Plane plane{principal.axes.col(0), principal.axes.col(0).dot(principal.centroid)};
  if (plane.offset_m < 0) plane.normal = -plane.normal, plane.offset_m = -plane.offset_m;
  return plane;
}

}  // namespace

Plane BoardPlane(const Rigid3d& T_color_board) {
  Plane plane{T_color_board.rotation() * Eigen::Vector3d::UnitZ(), 0};
  plane.offset_m = plane.normal.dot(T_color_board.translation());
  if (plane.offset_m < 0) plane.normal = -plane.normal, plane.offset_m = -plane.offset_m;
  return plane;
}

std::optional<PlaneFit> FitPlane(std::span<const Eigen::Vector3d> points, const PlaneFitOptions& options) {
  options.check();
  if (static_cast<int>(points.size()) < options.min_points) return std::nullopt;
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  std::optional<Plane> best;
  int best_count = 0;
  for (int i = 0; i < options.iterations; ++i) {
    const std::optional<Plane> candidate = PlaneThrough(points[pick(rng)], points[pick(rng)], points[pick(rng)]);
    if (!candidate) continue;
    int count = 0;
    for (const Eigen::Vector3d& p : points) count += Distance(*candidate, p) <= options.inlier_m;
    if (count > best_count) best = candidate, best_count = count;
  }
  if (!best || best_count < options.min_points) return std::nullopt;
  std::vector<Eigen::Vector3d> inliers;
  for (const Eigen::Vector3d& p : points)
    if (Distance(*best, p) <= options.inlier_m) inliers.push_back(p);
  PlaneFit fit{LeastSquaresPlane(inliers), static_cast<int>(inliers.size()), 0};
  double sum = 0;
  for (const Eigen::Vector3d& p : inliers) sum += std::pow(Distance(fit.plane, p), 2);
  fit.rms_mm = 1000.0 * std::sqrt(sum / static_cast<double>(inliers.size()));
  return fit;
}

namespace {

/// The smaller principal angle of the normals' scatter: how far they turn about the second axis.
double NormalSpreadDeg(std::span<const PlanePair> views) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const PlanePair& v : views) scatter += v.color.normal * v.color.normal.transpose();
  const Eigen::Vector3d s = Eigen::JacobiSVD<Eigen::Matrix3d>(scatter).singularValues();
  return DegFromRad(std::atan(std::sqrt(std::max(0.0, s(2)) / s(0))));
}

}  // namespace

DepthToColorResult EstimateDepthToColor(std::span<const PlanePair> views, const DepthToColorOptions& options) {
  options.check();
  const int n = static_cast<int>(views.size());
  if (n < options.min_views)
    throw InputError("depth-to-colour", Str("only ", n, " views with the board in both images (need ", options.min_views,
                                            "); record the board at several tilts"));
  DepthToColorResult result;
  result.normal_spread_deg = NormalSpreadDeg(views);
  // Rotation: R maximising sum n_c . R n_d (Kabsch on unit normals).
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (const PlanePair& v : views) H += v.depth.normal * v.color.normal.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  // Translation: n_c . t = d_c - d_d for every view, least squares.
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) A.row(i) = views[static_cast<size_t>(i)].color.normal.transpose(), b(i) = views[static_cast<size_t>(i)].color.offset_m - views[static_cast<size_t>(i)].depth.offset_m;
  const Eigen::JacobiSVD<Eigen::MatrixXd> lsq(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::Vector3d s = lsq.singularValues();
  if (!(s(2) > 1e-3 * s(0)))
    throw InputError("depth-to-colour", "the board's planes all face one way: tilt the board about two axes, 20-40 deg each way");
  result.T_color_depth = Rigid3d(Eigen::Quaterniond(R), lsq.solve(b));
  double sum_mm = 0, sum_deg = 0;
  for (const PlanePair& v : views) {
    const double e_mm = 1000.0 * (v.color.offset_m - v.depth.offset_m - v.color.normal.dot(result.T_color_depth.translation()));
    const double e_deg = DegFromRad(std::acos(std::clamp(v.color.normal.dot(R * v.depth.normal), -1.0, 1.0)));
    result.offset_error_mm.push_back(e_mm), result.normal_error_deg.push_back(e_deg);
    sum_mm += e_mm * e_mm, sum_deg += e_deg * e_deg;
  }
  result.offset_rms_mm = std::sqrt(sum_mm / n), result.normal_rms_deg = std::sqrt(sum_deg / n);
  if (result.normal_spread_deg < options.min_normal_spread_deg)
    result.warnings.push_back(Str("the board's normals spread only ", result.normal_spread_deg, " deg (want ", options.min_normal_spread_deg,
                                  "): the translation across them is uncertain; tilt the board more, about two axes"));
  return result;
}

}  // namespace mocap
