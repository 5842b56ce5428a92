#include "validate/icp.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mocap {
namespace {

/// First and second moments of the correspondences of one ICP iteration.
struct Moments {
  Eigen::Vector3d sum_source = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_target = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_cross = Eigen::Matrix3d::Zero();  // sum s t^T
  double sum_sq_distance = 0.0;
  int count = 0;

  void Add(const Eigen::Vector3d& s, const Eigen::Vector3d& t, double d2) {
    sum_source += s;
    sum_target += t;
    sum_cross += s * t.transpose();
    sum_sq_distance += d2;
    ++count;
  }
};

/// Kabsch/Umeyama from moments: H = sum (s - s_mean)(t - t_mean)^T, R = V diag(1, 1, det(V U^T)) U^T.
Rigid3d SolveFromMoments(const Moments& m) {
  const Eigen::Vector3d mean_s = m.sum_source / m.count;
  const Eigen::Vector3d mean_t = m.sum_target / m.count;
  const Eigen::Matrix3d H = m.sum_cross - m.count * mean_s * mean_t.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  const Eigen::Matrix3d R = svd.matrixV() * D * svd.matrixU().transpose();
  return Rigid3d(R, mean_t - R * mean_s);
}

Moments Correspond(const PointCloud& source, const KdTree& target, const Rigid3d& T, double gate_m, int stride) {
  const Eigen::Matrix3d R = T.rotation_matrix();
  const Eigen::Vector3d t = T.translation();
  const double gate_sq = gate_m * gate_m;
  Moments m;
  size_t index = 0;
  double d2 = 0.0;
  for (size_t i = 0; i < source.size(); i += static_cast<size_t>(stride)) {
    const Eigen::Vector3d& s = source[i];
    if (target.Nearest(R * s + t, gate_m, &index, &d2) && d2 <= gate_sq) m.Add(s, target.point(index), d2);
  }
  return m;
}

}  // namespace

void IcpOptions::check() const {
  if (!(max_correspondence_distance_m > 0) || !(initial_correspondence_distance_m >= max_correspondence_distance_m))
    throw InputError("IcpOptions", "need 0 < max_correspondence_distance_m <= initial_correspondence_distance_m");
  if (!(gate_shrink > 0 && gate_shrink <= 1)) throw InputError("IcpOptions", "gate_shrink must lie in (0, 1]");
  if (max_iterations < 1) throw InputError("IcpOptions", "max_iterations must be >= 1");
  if (!(translation_epsilon_m > 0) || !(rotation_epsilon_deg > 0))
    throw InputError("IcpOptions", "convergence thresholds must be positive");
  if (source_stride < 1) throw InputError("IcpOptions", "source_stride must be >= 1");
  if (min_correspondences < 3) throw InputError("IcpOptions", "min_correspondences must be >= 3");
}

std::string_view ToString(IcpStopReason reason) {
  switch (reason) {
    case IcpStopReason::kConverged: return "converged";
    case IcpStopReason::kMaxIterations: return "max_iterations";
    case IcpStopReason::kTooFewCorrespondences: return "too_few_correspondences";
    case IcpStopReason::kEmptyInput: return "empty_input";
  }
  return "unknown";
}

IcpResult AlignPointToPoint(const PointCloud& source, const KdTree& target, const Rigid3d& T_target_source_init,
                            const IcpOptions& options) {
  IcpResult result;
  result.T_target_source = T_target_source_init;
  if (source.empty() || target.size() == 0) return result;

  int stride = std::min<int>(options.source_stride, std::max<int>(1, static_cast<int>(source.size()) / 50));
  double gate_m = options.initial_correspondence_distance_m;
  result.reason = IcpStopReason::kMaxIterations;
  while (result.iterations < options.max_iterations) {
    const Moments m = Correspond(source, target, result.T_target_source, gate_m, stride);
    result.num_inliers = m.count;
    if (m.count < options.min_correspondences) {
      result.reason = IcpStopReason::kTooFewCorrespondences;
      break;
    }
    result.inlier_rmse_m = std::sqrt(m.sum_sq_distance / m.count);
    result.fitness = static_cast<double>(m.count) * stride / static_cast<double>(source.size());
    const Rigid3d next = SolveFromMoments(m);
    const double dt = TranslationDistanceM(next, result.T_target_source);
    const double dr = RotationDistanceDeg(next, result.T_target_source);
    result.T_target_source = next;
    ++result.iterations;
    const bool gate_final = gate_m <= options.max_correspondence_distance_m;
    if (gate_final && dt < options.translation_epsilon_m && dr < options.rotation_epsilon_deg) {
      if (stride == 1) {
        result.converged = true;
        result.reason = IcpStopReason::kConverged;
        break;
      }
      stride = 1;  // coarse phase done: finish on every point
    }
    gate_m = std::max(options.max_correspondence_distance_m, gate_m * options.gate_shrink);
  }
  result.fitness = std::min(result.fitness, 1.0);
  return result;
}

Rigid3d KabschTransform(const PointCloud& source, const PointCloud& target) {
  MOCAP_CHECK(source.size() == target.size() && source.size() >= 3, "Kabsch needs >= 3 paired points");
  Moments m;
  for (size_t i = 0; i < source.size(); ++i) m.Add(source[i], target[i], 0.0);
  return SolveFromMoments(m);
}

}  // namespace mocap
