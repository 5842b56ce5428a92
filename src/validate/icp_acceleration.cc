#include "validate/icp_acceleration.h"

#include <algorithm>
#include <cmath>

namespace mocap::icp_detail {

BeslMcKayAccelerator::BeslMcKayAccelerator(const PointCloud& source, double angle_deg, double max_factor)
    : cos_angle_(std::cos(RadFromDeg(angle_deg))), max_factor_(max_factor) {
  if (source.empty()) return;
  centroid_source_ = Centroid(source);
  double sum_sq = 0.0;
  for (const auto& p : source) sum_sq += (p - centroid_source_).squaredNorm();
  radius_m_ = std::max(1e-6, std::sqrt(sum_sq / static_cast<double>(source.size())));
}

Eigen::Matrix<double, 6, 1> BeslMcKayAccelerator::Delta(const Rigid3d& a, const Rigid3d& b) const {
  Eigen::Matrix<double, 6, 1> d;
  d.head<3>() = radius_m_ * Rigid3d(b.rotation() * a.rotation().conjugate(), Eigen::Vector3d::Zero()).rvec();
  d.tail<3>() = b * centroid_source_ - a * centroid_source_;
  return d;
}

double BeslMcKayAccelerator::StepLength(double last_length, double previous_length) const {
  // Arc positions along the path: u = -(l3 + l2), -l3, 0 for the last three poses (Besl & McKay's v).
  const double d1 = mse_m2_[1], d2 = mse_m2_[2], d3 = mse_m2_[3];
  const double u1 = -(last_length + previous_length), u2 = -last_length;
  const double slope = (d3 - d2) / last_length;
  if (!(slope < 0)) return 0.0;  // the error is not falling along the path: nothing to extrapolate
  const double v_line = -d3 / slope;  // where the line through the last two errors reaches zero
  // Parabola d(u) = a u^2 + b u + d3 through the three errors; its minimum, when it opens upwards.
  const double a = ((d1 - d3) / u1 - (d2 - d3) / u2) / (u1 - u2);
  const double b = (d2 - d3) / u2 - a * u2;
  const double v_parabola = a > 0 ? -b / (2 * a) : -1.0;
  const double v = v_parabola > 0 ? std::min(v_parabola, v_line) : v_line;
  return std::min(v, max_factor_ * last_length);
}

std::optional<Rigid3d> BeslMcKayAccelerator::Update(const Rigid3d& T_target_source, double mse_m2) {
  if (count_ == 4) {
    std::rotate(poses_.begin(), poses_.begin() + 1, poses_.end());
    std::rotate(mse_m2_.begin(), mse_m2_.begin() + 1, mse_m2_.end());
    --count_;
  }
  poses_[count_] = T_target_source;
  mse_m2_[count_] = mse_m2;
  if (++count_ < 4) return std::nullopt;
  const auto d1 = Delta(poses_[0], poses_[1]), d2 = Delta(poses_[1], poses_[2]), d3 = Delta(poses_[2], poses_[3]);
  const double l1 = d1.norm(), l2 = d2.norm(), l3 = d3.norm();
  if (!(l1 > 1e-12 && l2 > 1e-12 && l3 > 1e-12)) return std::nullopt;
  // Besl & McKay's test: both angles between successive updates below delta-theta.
  if (d3.dot(d2) < cos_angle_ * l3 * l2 || d2.dot(d1) < cos_angle_ * l2 * l1) return std::nullopt;
  const double v = StepLength(l3, l2);
  if (!(v > 0)) return std::nullopt;
  const double s = v / l3;
  const Rigid3d& last = poses_[3];
  const Rigid3d turn = Rigid3d::FromRvec(s * d3.head<3>() / radius_m_, Eigen::Vector3d::Zero());
  const Eigen::Quaterniond R = (turn.rotation() * last.rotation()).normalized();
  const Eigen::Vector3d centroid_target = last * centroid_source_ + s * d3.tail<3>();
  count_ = 0;
  return Rigid3d(R, centroid_target - R * centroid_source_);
}

}  // namespace mocap::icp_detail
