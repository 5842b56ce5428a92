#include "calibrate/pivot.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mocap {

void PivotOptions::check() const {
  if (min_samples < 4) throw InputError("PivotOptions.min_samples", Str("is ", min_samples, "; need >= 4"));
  if (!(min_rotation_deg > 0)) throw InputError("PivotOptions.min_rotation_deg", "must be positive");
  if (!(max_rms_mm > 0)) throw InputError("PivotOptions.max_rms_mm", "must be positive");
}

namespace {

double LargestRotationDeg(std::span<const Rigid3d> poses) {
  double largest = 0;
  for (size_t i = 0; i < poses.size(); ++i)
    for (size_t j = i + 1; j < poses.size(); ++j) largest = std::max(largest, RotationDistanceDeg(poses[i], poses[j]));
  return largest;
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
  Eigen::MatrixXd A(3 * n, 6);
  Eigen::VectorXd b(3 * n);
  for (int i = 0; i < n; ++i) {
    A.block<3, 3>(3 * i, 0) = T_tracker_pointer[static_cast<size_t>(i)].rotation().toRotationMatrix();
    A.block<3, 3>(3 * i, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(3 * i) = -T_tracker_pointer[static_cast<size_t>(i)].translation();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd x = svd.solve(b);
  result.p_pointer_tip = x.head<3>(), result.p_tracker_pivot = x.tail<3>();
  const Eigen::VectorXd s = svd.singularValues();
  result.condition = s(5) > 0 ? s(0) / s(5) : INFINITY;
  double sum = 0;
  for (const Rigid3d& T : T_tracker_pointer) sum += (T * result.p_pointer_tip - result.p_tracker_pivot).squaredNorm();
  result.rms_mm = 1000.0 * std::sqrt(sum / n);
  if (result.rms_mm > options.max_rms_mm)
    result.warnings.push_back(Str("tip residual ", result.rms_mm, " mm above ", options.max_rms_mm,
                                  " mm: the tip slipped in the divot or a marker was occluded; record again"));
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

}  // namespace mocap
