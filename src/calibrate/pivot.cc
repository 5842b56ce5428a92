#include "calibrate/pivot.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "calibrate/robust_stats.h"
#include "core/check.h"

namespace mocap {

void PivotOptions::check() const {
  if (min_samples < 4) throw InputError("PivotOptions.min_samples", Str("is ", min_samples, "; need >= 4"));
  if (!(min_rotation_deg > 0)) throw InputError("PivotOptions.min_rotation_deg", "must be positive");
  if (!(max_rms_mm > 0)) throw InputError("PivotOptions.max_rms_mm", "must be positive");
  if (!(outlier_mm > 0)) throw InputError("PivotOptions.outlier_mm", "must be positive");
}

namespace {

double LargestRotationDeg(std::span<const Rigid3d> poses) {
  double largest = 0;
  for (size_t i = 0; i < poses.size(); ++i)
    for (size_t j = i + 1; j < poses.size(); ++j) largest = std::max(largest, RotationDistanceDeg(poses[i], poses[j]));
  return largest;
}

/// Least-squares tip and pivot of the poses; the system's condition number.
void SolvePivot(std::span<const Rigid3d> poses, PivotResult& result) {
  const int n = static_cast<int>(poses.size());
  Eigen::MatrixXd A(3 * n, 6);
  Eigen::VectorXd b(3 * n);
  for (int i = 0; i < n; ++i) {
    A.block<3, 3>(3 * i, 0) = poses[static_cast<size_t>(i)].rotation().toRotationMatrix();
    A.block<3, 3>(3 * i, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * i) = -poses[static_cast<size_t>(i)].translation();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd x = svd.solve(b);
  result.p_pointer_tip = x.head<3>(), result.p_tracker_pivot = x.tail<3>();
  const Eigen::VectorXd s = svd.singularValues();
  result.condition = s(5) > 0 ? s(0) / s(5) : INFINITY;
}

double TipErrorM(const Rigid3d& T, const PivotResult& r) { return (T * r.p_pointer_tip - r.p_tracker_pivot).norm(); }

/// The poses that pivot about one tip: RANSAC over triples of poses turned at least 5 degrees apart
/// (the tip within `bound_m` of the pivot counts as agreeing), refitted on the largest consensus until
/// it stops growing. A fixed seed: the same recording gives the same tip.
std::vector<Rigid3d> PivotingPoses(std::span<const Rigid3d> poses, double bound_m) {
  std::mt19937 rng(1);
  std::uniform_int_distribution<size_t> pick(0, poses.size() - 1);
  auto consensus = [&](const PivotResult& r) {
    std::vector<Rigid3d> in;
    for (const Rigid3d& T : poses)
      if (TipErrorM(T, r) <= bound_m) in.push_back(T);
    return in;
  };
  std::vector<Rigid3d> best;
  for (int trial = 0; trial < 300; ++trial) {
    const std::array<Rigid3d, 3> triple = {poses[pick(rng)], poses[pick(rng)], poses[pick(rng)]};
    if (RotationDistanceDeg(triple[0], triple[1]) < 5 || RotationDistanceDeg(triple[0], triple[2]) < 5 ||
        RotationDistanceDeg(triple[1], triple[2]) < 5)
      continue;
    PivotResult r;
    SolvePivot(triple, r);
    std::vector<Rigid3d> in = consensus(r);
    if (in.size() > best.size()) best = std::move(in);
  }
  for (size_t previous = 0; best.size() > previous && best.size() >= 3;) {
    previous = best.size();
    PivotResult r;
    SolvePivot(best, r);
    best = consensus(r);
  }
  return best;
}

}  // namespace

PivotResult CalibratePivot(std::span<const Rigid3d> T_tracker_pointer, const PivotOptions& options) {
  options.check();
  const int n = static_cast<int>(T_tracker_pointer.size());
  if (n < options.min_samples)
    throw InputError("pivot", Str("too few pointer poses: ", n, " (need ", options.min_samples,
                                  "); record the pointer pivoting in its divot for a few seconds"));
  PivotResult result;
  result.rotation_spread_deg = LargestRotationDeg(T_tracker_pointer);
  if (result.rotation_spread_deg < options.min_rotation_deg)
    throw InputError("pivot", Str("the pointer turned only ", result.rotation_spread_deg, " deg (need ", options.min_rotation_deg,
                                  "); tilt it about its tip in two directions, 20-40 deg each way"));
  const std::vector<Rigid3d> kept = PivotingPoses(T_tracker_pointer, options.outlier_mm / 1000.0);
  if (static_cast<int>(kept.size()) < options.min_samples)
    throw InputError("pivot", Str("only ", kept.size(), " of ", n, " poses agree on one tip within ", options.outlier_mm,
                                  " mm; keep the tip in the divot while pivoting"));
  SolvePivot(kept, result);
  result.samples_used = static_cast<int>(kept.size()), result.samples_dropped = n - result.samples_used;
  double sum = 0;
  for (const Rigid3d& T : kept) sum += std::pow(TipErrorM(T, result), 2);
  result.rms_mm = 1000.0 * std::sqrt(sum / result.samples_used);
  if (result.rms_mm > options.max_rms_mm)
    result.warnings.push_back(Str("tip residual ", result.rms_mm, " mm above ", options.max_rms_mm,
                                  " mm: the tip slipped in the divot or a marker was occluded; record again"));
  if (result.samples_dropped > n / 4)
    result.warnings.push_back(Str(result.samples_dropped, " of ", n, " poses were not pivoting about the tip and were dropped; "
                                  "record only the pivoting (or give its time span)"));
  return result;
}

PairedPointResult RegisterPairedPoints(std::span<const Eigen::Vector3d> p_objbody, std::span<const Eigen::Vector3d> p_mesh) {
  if (p_objbody.size() != p_mesh.size())
    throw InputError("paired points", Str(p_objbody.size(), " touched points for ", p_mesh.size(), " landmarks"));
  const int n = static_cast<int>(p_mesh.size());
  if (n < 3) throw InputError("paired points", Str("only ", n, " landmark pairs; touch at least 3 (4 or more recommended)"));
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (int i = 0; i < n; ++i) src.col(i) = p_mesh[static_cast<size_t>(i)], dst.col(i) = p_objbody[static_cast<size_t>(i)];
  // Collinear landmarks leave the rotation about their line free: the centred scatter's second
  // singular value then vanishes relative to the first.
  const Eigen::Matrix3Xd centred = src.colwise() - src.rowwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  if (!(sv(1) > 1e-3 * sv(0)) || sv(0) <= 0)
    throw InputError("paired points", "the landmarks lie (nearly) on one line; choose landmarks spread over the object");
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
  PairedPointResult result;
  result.T_objbody_mesh = Rigid3d::FromMatrix4(T);
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double e = (result.T_objbody_mesh * src.col(i) - dst.col(i)).norm();
    result.fre_mm.push_back(1000.0 * e);
    sum += e * e;
  }
  result.fre_rms_mm = 1000.0 * std::sqrt(sum / n);
  return result;
}

void TouchOptions::check() const {
  if (!(min_still_s > 0)) throw InputError("TouchOptions.min_still_s", "must be positive");
  if (!(still_radius_mm > 0)) throw InputError("TouchOptions.still_radius_mm", "must be positive");
  if (!(max_gap_s > 0)) throw InputError("TouchOptions.max_gap_s", "must be positive");
  if (!(max_mismatch_mm > 0)) throw InputError("TouchOptions.max_mismatch_mm", "must be positive");
}

namespace {

Touch SummariseRest(std::span<const int64_t> stamps_ns, std::span<const Eigen::Vector3d> p, const std::vector<size_t>& in) {
  Touch touch;
  touch.start_ns = stamps_ns[in.front()], touch.end_ns = stamps_ns[in.back()], touch.samples = static_cast<int>(in.size());
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (size_t i : in) values.push_back(p[i](axis));
    touch.p_objbody(axis) = Median(std::move(values));
  }
  double sum = 0;
  for (size_t i : in) sum += (p[i] - touch.p_objbody).squaredNorm();
  touch.spread_mm = 1000.0 * std::sqrt(sum / static_cast<double>(in.size()));
  return touch;
}

}  // namespace

std::vector<Touch> FindTouches(std::span<const int64_t> stamps_ns, std::span<const Eigen::Vector3d> p_objbody_tip,
                               const TouchOptions& options) {
  options.check();
  if (stamps_ns.size() != p_objbody_tip.size())
    throw InputError("touches", Str(stamps_ns.size(), " stamps for ", p_objbody_tip.size(), " tip positions"));
  const double radius_m = options.still_radius_mm / 1000.0;
  const auto min_ns = static_cast<int64_t>(options.min_still_s * 1e9), gap_ns = static_cast<int64_t>(options.max_gap_s * 1e9);
  std::vector<Touch> touches;
  size_t begin = 0;
  while (begin < stamps_ns.size()) {
    // Grow the rest while the samples stay near the running mean of those in it; a single noisy sample
    // (the tip sits far from the markers, so their noise is magnified there) is skipped, and only
    // `kOutsideToEnd` in a row, or a tracking gap, end the rest.
    constexpr int kOutsideToEnd = 3;
    std::vector<size_t> in = {begin};
    Eigen::Vector3d sum = p_objbody_tip[begin];
    int outside = 0;
    for (size_t i = begin + 1; i < stamps_ns.size() && outside < kOutsideToEnd && stamps_ns[i] - stamps_ns[in.back()] <= gap_ns; ++i) {
      if ((p_objbody_tip[i] - sum / static_cast<double>(in.size())).norm() > radius_m) {
        ++outside;
        continue;
      }
      outside = 0, sum += p_objbody_tip[i], in.push_back(i);
    }
    if (stamps_ns[in.back()] - stamps_ns[begin] >= min_ns) {
      touches.push_back(SummariseRest(stamps_ns, p_objbody_tip, in));
      begin = in.back() + 1;
    } else {
      ++begin;
    }
  }
  return touches;
}

namespace {

/// RMS over pairs of |d(touch a, touch b) - d(landmark a, landmark b)| for the chosen touches.
double DistanceMismatch(std::span<const Touch> touches, std::span<const Eigen::Vector3d> p_mesh, const std::vector<int>& chosen) {
  double sum = 0;
  int pairs = 0;
  for (size_t a = 0; a < chosen.size(); ++a)
    for (size_t b = a + 1; b < chosen.size(); ++b, ++pairs) {
      const double d_touch = (touches[static_cast<size_t>(chosen[a])].p_objbody - touches[static_cast<size_t>(chosen[b])].p_objbody).norm();
      sum += std::pow(d_touch - (p_mesh[a] - p_mesh[b]).norm(), 2);
    }
  return pairs > 0 ? 1000.0 * std::sqrt(sum / pairs) : 0.0;
}

}  // namespace

TouchMatch MatchTouchesToLandmarks(std::span<const Touch> touches, std::span<const Eigen::Vector3d> p_mesh) {
  const int n = static_cast<int>(p_mesh.size()), m = static_cast<int>(touches.size());
  if (m < n) throw InputError("touches", Str("the pointer rested ", m, " times for ", n, " landmarks: touch every landmark, in the file's order"));
  if (m > 24) throw InputError("touches", Str("the pointer rested ", m, " times; record only the touching (or give its time span)"));
  // Every increasing choice of n of the m rests (at most C(24, 12), about 2.7 million, in practice a few hundred).
  std::vector<int> chosen(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) chosen[static_cast<size_t>(i)] = i;
  TouchMatch best{chosen, DistanceMismatch(touches, p_mesh, chosen)};
  while (true) {
    int i = n - 1;
    while (i >= 0 && chosen[static_cast<size_t>(i)] == m - n + i) --i;
    if (i < 0) break;
    ++chosen[static_cast<size_t>(i)];
    for (int j = i + 1; j < n; ++j) chosen[static_cast<size_t>(j)] = chosen[static_cast<size_t>(j - 1)] + 1;
    const double mismatch = DistanceMismatch(touches, p_mesh, chosen);
    if (mismatch < best.distance_rms_mm) best = {chosen, mismatch};
  }
  return best;
}

}  // namespace mocap
