#include "validate/icp.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "core/check.h"
#include "validate/icp_acceleration.h"
#include "validate/search_memory.h"

namespace mocap {
namespace {

/// First and second moments of the correspondences of one ICP iteration.
struct Moments {
  Eigen::Vector3d sum_source = Eigen::Vector3d::Zero();
  Eigen::Vector3d sum_target = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum_cross = Eigen::Matrix3d::Zero();  // sum s t^T
  double sum_sq_source = 0.0;                           // sum |s|^2
  double sum_sq_target = 0.0;                           // sum |t|^2
  double sum_sq_distance = 0.0;
  int count = 0;
  int visited = 0;  ///< source points queried (with or without a correspondence)

  void Add(const Eigen::Vector3d& s, const Eigen::Vector3d& t, double d2) {
    sum_source += s;
    sum_target += t;
    sum_cross += s * t.transpose();
    sum_sq_source += s.squaredNorm();
    sum_sq_target += t.squaredNorm();
    sum_sq_distance += d2;
    ++count;
  }
};

/// sum |R s + t_T - t|^2 over the correspondences of `m` at the pose T, from the moments alone:
/// sum |s|^2 + sum |t|^2 + n |t_T|^2 + 2 t_T . (R sum s - sum t) - 2 tr(R sum s t^T).
double ResidualAt(const Moments& m, const Rigid3d& T) {
  const Eigen::Matrix3d R = T.rotation_matrix();
  const Eigen::Vector3d& t = T.translation();
  const double r = m.sum_sq_source + m.sum_sq_target + m.count * t.squaredNorm() +
                   2.0 * t.dot(R * m.sum_source - m.sum_target) - 2.0 * (R * m.sum_cross).trace();
  return std::max(0.0, r);
}

/// Mean truncated squared error: points without a correspondence within the gate count as gate^2, so
/// that a pose cannot look better by losing correspondences.
double TruncatedError(double sum_sq_m2, const Moments& m, double gate_m) {
  return (sum_sq_m2 + (m.visited - m.count) * gate_m * gate_m) / std::max(1, m.visited);
}

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

/// One correspondence pass, from each point's last search.
Moments Correspond(const PointCloud& source, const PointGrid& target, const Rigid3d& T, double gate_m, int stride,
                   std::vector<SearchMemory>* searches) {
  const Eigen::Matrix3d R = T.rotation_matrix();
  const Eigen::Vector3d t = T.translation();
  Moments m;
  double d2 = 0.0;
  for (size_t i = 0; i < source.size(); i += static_cast<size_t>(stride)) {
    const Eigen::Vector3d& s = source[i];
    SearchMemory& last = (*searches)[i];
    ++m.visited;
    if (NearestRemembered(target, R * s + t, gate_m, &last, &d2)) m.Add(s, target.point(last.match), d2);
  }
  return m;
}

/// An extrapolated pose on trial (IcpOptions::accelerate): the pose it came from and that pose's error.
struct Trial {
  Rigid3d T_from;
  double error_m2 = 0.0;
};

/// Feeds the update just made (*T, from the correspondences `m`) to the accelerator; when it
/// extrapolates, *T becomes the extrapolated pose and the returned trial remembers where it came from.
std::optional<Trial> Extrapolate(const Moments& m, double gate_m, icp_detail::BeslMcKayAccelerator* accelerator,
                                 Rigid3d* T) {
  const double error_m2 = TruncatedError(ResidualAt(m, *T), m, gate_m);
  const std::optional<Rigid3d> jump = accelerator->Update(*T, error_m2);
  if (!jump) return std::nullopt;
  const Trial trial{*T, error_m2};
  *T = *jump;
  return trial;
}

/// Ends a trial on the pass `m` made at the extrapolated pose: when its truncated error exceeds that of
/// the pose it came from, *T goes back there and true is returned (the pass must be redone).
bool UndoWorseTrial(const Moments& m, double gate_m, std::optional<Trial>* trial, Rigid3d* T) {
  if (!*trial) return false;
  const bool worse = TruncatedError(m.sum_sq_distance, m, gate_m) > (*trial)->error_m2;
  if (worse) *T = (*trial)->T_from;
  trial->reset();
  return worse;
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
  if (!(acceleration_angle_deg > 0 && acceleration_angle_deg < 90))
    throw InputError("IcpOptions", "acceleration_angle_deg must lie in (0, 90)");
  if (!(acceleration_max_factor >= 1)) throw InputError("IcpOptions", "acceleration_max_factor must be >= 1");
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

IcpResult AlignPointToPoint(const PointCloud& source, const PointGrid& target, const Rigid3d& T_target_source_init,
                            const IcpOptions& options) {
  IcpResult result;
  result.T_target_source = T_target_source_init;
  if (source.empty() || target.size() == 0) return result;

  int stride = std::min<int>(options.source_stride, std::max<int>(1, static_cast<int>(source.size()) / 50));
  double gate_m = options.initial_correspondence_distance_m;
  std::optional<icp_detail::BeslMcKayAccelerator> accelerator;
  if (options.accelerate)
    accelerator.emplace(source, options.acceleration_angle_deg, options.acceleration_max_factor);
  std::optional<Trial> trial;
  std::vector<SearchMemory> searches(source.size());
  result.reason = IcpStopReason::kMaxIterations;
  while (result.iterations < options.max_iterations) {
    const Moments m = Correspond(source, target, result.T_target_source, gate_m, stride, &searches);
    if (UndoWorseTrial(m, gate_m, &trial, &result.T_target_source)) continue;  // redo the pass from there
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
      if (accelerator) accelerator->Reset();
    } else if (accelerator && gate_final) {
      trial = Extrapolate(m, gate_m, &*accelerator, &result.T_target_source);
    }
    gate_m = std::max(options.max_correspondence_distance_m, gate_m * options.gate_shrink);
  }
  if (trial) result.T_target_source = trial->T_from;  // an extrapolation never checked is not reported
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
