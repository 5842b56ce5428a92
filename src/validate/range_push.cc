#include "validate/range_push.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "core/check.h"

namespace mocap {

void RangePushOptions::check() const {
  if (!(min_information > 0 && min_information < 1)) throw InputError("RangePushOptions", "min_information must lie in (0, 1)");
  if (!(gate_m > 0)) throw InputError("RangePushOptions", "gate_m must be positive");
  if (iterations < 0) throw InputError("RangePushOptions", "iterations must be >= 0");
  if (!(stop_m > 0)) throw InputError("RangePushOptions", "stop_m must be positive");
}

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

struct PushEquations {
  Matrix6d A = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero(), c = Vector6d::Zero();
  double d = 0.0, e = 0.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius_m = 1.0;
};

/// The point-to-plane normal equations of the pose (A, b: analysis coordinates about `center`, as
/// observability.h) and of the push (c: its column against the pose's, d: its own, e: its right-hand
/// side), robustly weighted means over the matches. The push lies along the rays from `tof_center`.
PushEquations Build(const PointCloud& points, const PointCloud& normals, const Rigid3d& T, const Eigen::Vector3d& tof_center,
                    double push_m, const std::vector<CropMatch>& matches, double robust_sigmas) {
  PushEquations eq;
  std::tie(eq.center, eq.radius_m) = AnalysisCentre(points, matches);
  const Eigen::Matrix3d R = T.rotation_matrix();
  std::vector<double> residuals, push_column;
  for (const auto& [i, s] : matches) {
    const Eigen::Vector3d p = T * points[i], n = R * normals[i], u = (p - tof_center).normalized();
    const double cos_theta = std::min(1.0, std::abs(n.dot(u)));
    push_column.push_back((1.0 - cos_theta) * n.dot(u));
    residuals.push_back(n.dot(p - s) + push_m * push_column.back());
  }
  const std::vector<double> weights = RobustWeights(residuals, robust_sigmas, kMinRobustScaleM);
  double weight_sum = 0;
  for (size_t k = 0; k < matches.size(); ++k) {
    const size_t i = matches[k].first;
    const Vector6d J = AnalysisRow(points[i], normals[i], eq.center, eq.radius_m);
    const double w = weights[k], g = push_column[k], r = residuals[k];
    eq.A += w * J * J.transpose();
    eq.b += w * J * r;
    eq.c += w * J * g;
    eq.d += w * g * g;
    eq.e += w * g * r;
    weight_sum += w;
  }
  eq.A /= weight_sum, eq.b /= weight_sum, eq.c /= weight_sum, eq.d /= weight_sum, eq.e /= weight_sum;
  return eq;
}

/// The Gauss-Newton step of equations (A, b) along their eigen-directions with at least `min_information`.
Vector6d StepOf(const Matrix6d& A, const Vector6d& b, double min_information) {
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(A);
  Vector6d step = Vector6d::Zero();
  for (int k = 0; k < 6; ++k)
    if (eig.eigenvalues()(k) >= min_information)
      step -= eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(b) / eig.eigenvalues()(k));
  return step;
}

}  // namespace

RangePushFit FitWithRangePush(const ModelCrop& crop, const Rigid3d& T_camera_object_init, const PointGrid& scene_camera,
                              const Eigen::Vector3d& tof_center_camera, const RangePushOptions& options,
                              const ObservabilityOptions& observability) {
  const PointCloud& points = crop.points_model;
  const PointCloud normals = NormalsOf(crop, T_camera_object_init, observability.normal_radius_m);
  RangePushFit out;
  out.T_camera_object = T_camera_object_init;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    const std::vector<CropMatch> matches = MatchCrop(points, out.T_camera_object, scene_camera, options.gate_m, observability.max_points);
    if (matches.size() < 10) return out;
    const PushEquations eq =
        Build(points, normals, out.T_camera_object, tof_center_camera, out.push_m, matches, observability.robust_sigmas);
    if (!(eq.d > 1e-12)) return out;  // every point faces the camera: no deformation to tell apart
    Vector6d step = StepOf(eq.A - eq.c * eq.c.transpose() / eq.d, eq.b - eq.c * (eq.e / eq.d), options.min_information);
    double push_step_m = -(eq.e + eq.c.dot(step)) / eq.d;
    // Multipath only adds path: a push that would go negative is held at zero and the pose stepped alone.
    if (out.push_m + push_step_m < 0) {
      push_step_m = -out.push_m;
      step = StepOf(eq.A, eq.b + eq.c * push_step_m, options.min_information);
    }
    out.T_camera_object = MovedAlong(out.T_camera_object, step, eq.center, eq.radius_m);
    out.push_m += push_step_m;
    out.iterations = iteration + 1;
    out.converged = step.tail<3>().norm() < options.stop_m && step.head<3>().norm() < options.stop_m &&
                    std::abs(push_step_m) < options.stop_m;
    if (out.converged) break;
  }
  return out;
}

}  // namespace mocap
