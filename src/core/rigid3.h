#pragma once
// Rigid transforms named by the frames they map between (DESIGN.md "Conventions"):
// T_a_b maps a point in frame b into frame a, p_a = T_a_b * p_b, so T_a_c = T_a_b * T_b_c.
// Units: metres and radians. Quaternion element order is spelled out in every name (wxyz, xyzw),
// because peers' worst bugs are exactly that.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <span>
#include <vector>

namespace mocap {

class Rigid3d {
 public:
  Rigid3d() = default;
  /// Precondition: `rotation` has norm within 1e-3 of 1 (tracker quaternions are only approximately
  /// unit); it is normalised here. Aborts otherwise: a non-unit rotation is a bug upstream.
  Rigid3d(const Eigen::Quaterniond& rotation, const Eigen::Vector3d& translation_m);
  /// Precondition: `R` is a rotation matrix (orthonormal within 1e-6, det +1).
  Rigid3d(const Eigen::Matrix3d& R, const Eigen::Vector3d& translation_m);

  static Rigid3d Identity() { return {}; }
  /// From a 4x4 homogeneous matrix whose upper-left 3x3 is a rotation (checked) and last row 0 0 0 1.
  static Rigid3d FromMatrix4(const Eigen::Matrix4d& T);
  /// Rodrigues vector (axis * angle, radians), as cv::Rodrigues and the label files use.
  static Rigid3d FromRvec(const Eigen::Vector3d& rvec_rad, const Eigen::Vector3d& translation_m);
  static Rigid3d FromQuatWxyz(double w, double x, double y, double z, const Eigen::Vector3d& translation_m);
  static Rigid3d FromQuatXyzw(double x, double y, double z, double w, const Eigen::Vector3d& translation_m);

  const Eigen::Quaterniond& rotation() const { return rotation_; }
  const Eigen::Vector3d& translation() const { return translation_; }
  Eigen::Matrix3d rotation_matrix() const { return rotation_.toRotationMatrix(); }
  Eigen::Matrix4d matrix4() const;
  Eigen::Isometry3d isometry() const;
  /// Rodrigues vector (radians), angle in [0, pi].
  Eigen::Vector3d rvec() const;
  /// Quaternion as (w, x, y, z) with w >= 0 (the sign is fixed so files are reproducible).
  Eigen::Vector4d quat_wxyz() const;
  Eigen::Vector4d quat_xyzw() const;

  Rigid3d inverse() const;
  Rigid3d operator*(const Rigid3d& other) const;
  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const { return rotation_ * point + translation_; }

 private:
  Eigen::Quaterniond rotation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation_ = Eigen::Vector3d::Zero();
};

/// Euclidean distance between the translations, metres.
double TranslationDistanceM(const Rigid3d& a, const Rigid3d& b);
/// Angle of the relative rotation a^-1 b, degrees in [0, 180].
double RotationDistanceDeg(const Rigid3d& a, const Rigid3d& b);
/// Angle between the rotation axes of a and b, degrees in [0, 180] (the paper's "rotation axis" error);
/// 0 when either rotation is below 1e-9 rad.
double RotationAxisDistanceDeg(const Rigid3d& a, const Rigid3d& b);

/// Mean of rigid transforms: arithmetic mean of translations and the quaternion average of
/// Markley et al. (2007), the eigenvector of sum(q q^T) with the largest eigenvalue, which is
/// insensitive to the q/-q sign ambiguity. Precondition: poses non-empty; weights, if given, match and
/// are non-negative with positive sum.
Rigid3d AveragePoses(std::span<const Rigid3d> poses, std::span<const double> weights = {});

/// Geodesic interpolation: translation linear, rotation SLERP along the shorter arc; alpha in [0, 1].
Rigid3d Interpolate(const Rigid3d& a, const Rigid3d& b, double alpha);

double DegFromRad(double rad);
double RadFromDeg(double deg);

}  // namespace mocap
