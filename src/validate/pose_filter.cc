#include "validate/pose_filter.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mocap {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
// Error-state blocks: rotation, position, angular velocity, velocity.
constexpr int kRot = 0, kPos = 3, kAngVel = 6, kVel = 9;

}  // namespace

Eigen::Quaterniond ExpSO3(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-12) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle));
}

Eigen::Vector3d LogSO3(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec();
  return q.vec() / s * (2.0 * std::atan2(s, q.w()));
}

void PoseFilterOptions::check() const {
  const double positives[] = {accel_sigma_mps2, angular_accel_sigma_radps2, position_sigma_m, rotation_sigma_deg,
                              gate_chi2, initial_velocity_sigma_mps, initial_angular_velocity_sigma_radps,
                              max_position_sigma_m};
  for (double v : positives)
    if (!(v > 0)) throw InputError("PoseFilterOptions", "noise levels, gate and limits must be positive");
  if (!(score_noise_exponent >= 0)) throw InputError("PoseFilterOptions", "score_noise_exponent must be >= 0");
}

PoseFilter::PoseFilter(const PoseFilterOptions& options) : options_(options) { options_.check(); }

void PoseFilter::Initialize(const Rigid3d& T_world_object, int64_t stamp_ns, double score) {
  initialized_ = true;
  stamp_ns_ = stamp_ns;
  rotation_ = T_world_object.rotation();
  position_ = T_world_object.translation();
  angular_velocity_.setZero();
  velocity_.setZero();
  const double k = std::pow(std::max(score, 1e-3), -options_.score_noise_exponent);
  P_.setZero();
  P_.block<3, 3>(kRot, kRot).diagonal().setConstant(std::pow(k * RadFromDeg(options_.rotation_sigma_deg), 2));
  P_.block<3, 3>(kPos, kPos).diagonal().setConstant(std::pow(k * options_.position_sigma_m, 2));
  P_.block<3, 3>(kAngVel, kAngVel).diagonal().setConstant(std::pow(options_.initial_angular_velocity_sigma_radps, 2));
  P_.block<3, 3>(kVel, kVel).diagonal().setConstant(std::pow(options_.initial_velocity_sigma_mps, 2));
}

void PoseFilter::Predict(int64_t stamp_ns) {
  MOCAP_CHECK(initialized_, "Predict before Initialize");
  if (stamp_ns <= stamp_ns_) return;
  const double dt = static_cast<double>(stamp_ns - stamp_ns_) * 1e-9;
  stamp_ns_ = stamp_ns;
  rotation_ = (ExpSO3(angular_velocity_ * dt) * rotation_).normalized();
  position_ += velocity_ * dt;
  Matrix12d F = Matrix12d::Identity();
  F.block<3, 3>(kRot, kAngVel).diagonal().setConstant(dt);
  F.block<3, 3>(kPos, kVel).diagonal().setConstant(dt);
  // Discrete white-acceleration noise: [dt^3/3, dt^2/2; dt^2/2, dt] * sigma^2 per (value, rate) pair.
  Matrix12d Q = Matrix12d::Zero();
  const auto add_pair = [&](int value, int rate, double sigma) {
    const double q = sigma * sigma;
    Q.block<3, 3>(value, value).diagonal().setConstant(q * dt * dt * dt / 3);
    Q.block<3, 3>(value, rate).diagonal().setConstant(q * dt * dt / 2);
    Q.block<3, 3>(rate, value).diagonal().setConstant(q * dt * dt / 2);
    Q.block<3, 3>(rate, rate).diagonal().setConstant(q * dt);
  };
  add_pair(kRot, kAngVel, options_.angular_accel_sigma_radps2);
  add_pair(kPos, kVel, options_.accel_sigma_mps2);
  P_ = F * P_ * F.transpose() + Q;
}

FilterUpdate PoseFilter::Update(const Rigid3d& T_world_object_measured, double score) {
  MOCAP_CHECK(initialized_, "Update before Initialize");
  FilterUpdate out;
  Vector6d z;
  z.head<3>() = LogSO3(T_world_object_measured.rotation() * rotation_.conjugate());
  z.tail<3>() = T_world_object_measured.translation() - position_;
  const double k = std::pow(std::max(score, 1e-3), -options_.score_noise_exponent);
  Matrix6d R = Matrix6d::Zero();
  R.block<3, 3>(0, 0).diagonal().setConstant(std::pow(k * RadFromDeg(options_.rotation_sigma_deg), 2));
  R.block<3, 3>(3, 3).diagonal().setConstant(std::pow(k * options_.position_sigma_m, 2));
  // H selects the rotation and position error blocks.
  const Matrix6d S = P_.topLeftCorner<6, 6>() + R;
  const Eigen::LDLT<Matrix6d> S_ldlt(S);
  out.mahalanobis_sq = z.dot(S_ldlt.solve(z));
  if (!(out.mahalanobis_sq <= options_.gate_chi2)) return out;
  const Eigen::Matrix<double, 12, 6> K = S_ldlt.solve(P_.topRows<6>()).transpose();  // P H^T S^-1
  const Eigen::Matrix<double, 12, 1> dx = K * z;
  rotation_ = (ExpSO3(dx.segment<3>(kRot)) * rotation_).normalized();
  position_ += dx.segment<3>(kPos);
  angular_velocity_ += dx.segment<3>(kAngVel);
  velocity_ += dx.segment<3>(kVel);
  Eigen::Matrix<double, 12, 12> I_KH = Matrix12d::Identity();
  I_KH.leftCols<6>() -= K;
  P_ = I_KH * P_ * I_KH.transpose() + K * R * K.transpose();  // Joseph form keeps P symmetric PSD
  out.accepted = true;
  return out;
}

double PoseFilter::position_sigma_m() const {
  return std::sqrt(P_.block<3, 3>(kPos, kPos).diagonal().maxCoeff());
}

}  // namespace mocap
