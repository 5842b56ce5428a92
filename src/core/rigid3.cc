#include "core/rigid3.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "core/check.h"

namespace mocap {

Rigid3d::Rigid3d(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation_m)
    : rotation_(rotation), translation_(translation_m) {
  const double norm = rotation.norm();
  MOCAP_CHECK(std::abs(norm - 1.0) < 1e-3, "quaternion norm ", norm, " is not 1");
  rotation_.normalize();
}

Rigid3d::Rigid3d(const Eigen::Matrix3d& R, const Eigen::Vector3d& translation_m) : translation_(translation_m) {
  const double orthogonality = (R * R.transpose() - Eigen::Matrix3d::Identity()).norm();
  MOCAP_CHECK(orthogonality < 1e-6 && R.determinant() > 0, "not a rotation matrix (|RR^T - I| = ",
              orthogonality, ", det = ", R.determinant(), ")");
  rotation_ = Eigen::Quaterniond(R).normalized();
}

Rigid3d Rigid3d::FromMatrix4(const Eigen::Matrix4d& T) {
  MOCAP_CHECK(T.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)), "last row of a rigid transform is not 0 0 0 1");
  return Rigid3d(Eigen::Matrix3d(T.topLeftCorner<3, 3>()), T.topRightCorner<3, 1>());
}

Rigid3d Rigid3d::FromRvec(const Eigen::Vector3d& rvec_rad, const Eigen::Vector3d& translation_m) {
  const double angle = rvec_rad.norm();
  if (angle < 1e-15) return Rigid3d(Eigen::Quaterniond::Identity(), translation_m);
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle, rvec_rad / angle)), translation_m);
}

Rigid3d Rigid3d::FromQuatWxyz(double w, double x, double y, double z, const Eigen::Vector3d& translation_m) {
  return Rigid3d(Eigen::Quaterniond(w, x, y, z), translation_m);
}

Rigid3d Rigid3d::FromQuatXyzw(double x, double y, double z, double w, const Eigen::Vector3d& translation_m) {
  return Rigid3d(Eigen::Quaterniond(w, x, y, z), translation_m);
}

Eigen::Matrix4d Rigid3d::matrix4() const {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T.topLeftCorner<3, 3>() = rotation_matrix();
  T.topRightCorner<3, 1>() = translation_;
  return T;
}

Eigen::Isometry3d Rigid3d::isometry() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_matrix();
  T.translation() = translation_;
  return T;
}

Eigen::Vector3d Rigid3d::rvec() const {
  // Take the w >= 0 representative so the angle lies in [0, pi].
  const Eigen::Vector4d q = quat_wxyz();
  const Eigen::Vector3d v = q.tail<3>();
  const double s = v.norm();
  if (s < 1e-15) return Eigen::Vector3d::Zero();
  const double angle = 2.0 * std::atan2(s, q[0]);
  return v / s * angle;
}

Eigen::Vector4d Rigid3d::quat_wxyz() const {
  Eigen::Vector4d q(rotation_.w(), rotation_.x(), rotation_.y(), rotation_.z());
  return q[0] < 0 ? Eigen::Vector4d(-q) : q;
}

Eigen::Vector4d Rigid3d::quat_xyzw() const {
  const Eigen::Vector4d q = quat_wxyz();
  return {q[1], q[2], q[3], q[0]};
}

Rigid3d Rigid3d::inverse() const {
  const Eigen::Quaterniond r = rotation_.conjugate();
  return Rigid3d(r, -(r * translation_));
}

Rigid3d Rigid3d::operator*(const Rigid3d& other) const {
  return Rigid3d((rotation_ * other.rotation_).normalized(), rotation_ * other.translation_ + translation_);
}

double TranslationDistanceM(const Rigid3d& a, const Rigid3d& b) {
  return (a.translation() - b.translation()).norm();
}

double RotationDistanceDeg(const Rigid3d& a, const Rigid3d& b) {
  return DegFromRad(a.rotation().angularDistance(b.rotation()));
}

double RotationAxisDistanceDeg(const Rigid3d& a, const Rigid3d& b) {
  const Eigen::Vector3d ra = a.rvec();
  const Eigen::Vector3d rb = b.rvec();
  if (ra.norm() < 1e-9 || rb.norm() < 1e-9) return 0.0;
  // (n, theta) and (-n, 2 pi - theta) are the same rotation, and near half a turn the rotation vector's
  // axis flips with the slightest change: b's axis is taken in whichever form lies nearer a's vector
  // (two poses half a turn from the camera, 0.4 deg apart, otherwise differ by a 180 deg axis).
  const Eigen::Vector3d rb_other = -(2.0 * std::numbers::pi - rb.norm()) * rb.normalized();
  const Eigen::Vector3d nb = (ra - rb_other).norm() < (ra - rb).norm() ? Eigen::Vector3d(-rb.normalized()) : rb.normalized();
  const double c = std::clamp(ra.normalized().dot(nb), -1.0, 1.0);
  return DegFromRad(std::acos(c));
}

Rigid3d AveragePoses(std::span<const Rigid3d> poses, std::span<const double> weights) {
  MOCAP_CHECK(!poses.empty(), "averaging no poses");
  MOCAP_CHECK(weights.empty() || weights.size() == poses.size(), "weights do not match poses");
  Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double total = 0.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    const double w = weights.empty() ? 1.0 : weights[i];
    MOCAP_CHECK(w >= 0.0, "negative weight");
    const Eigen::Vector4d q = poses[i].quat_wxyz();
    M += w * q * q.transpose();
    t += w * poses[i].translation();
    total += w;
  }
  MOCAP_CHECK(total > 0.0, "weights sum to zero");
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> solver(M);
  const Eigen::Vector4d q = solver.eigenvectors().col(3);  // eigenvalues ascend
  return Rigid3d(Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized(), t / total);
}

Rigid3d Interpolate(const Rigid3d& a, const Rigid3d& b, double alpha) {
  // Eigen's slerp takes the shorter arc (it flips the sign when the dot product is negative).
  return Rigid3d(a.rotation().slerp(alpha, b.rotation()).normalized(),
                 (1.0 - alpha) * a.translation() + alpha * b.translation());
}

double DegFromRad(double rad) { return rad * 180.0 / std::numbers::pi; }
double RadFromDeg(double deg) { return deg * std::numbers::pi / 180.0; }

}  // namespace mocap
