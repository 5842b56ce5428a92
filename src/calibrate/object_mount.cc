#include "calibrate/object_mount.h"

#include <algorithm>
#include <cmath>

#include "calibrate/robust_stats.h"
#include "core/check.h"

namespace mocap {
namespace {

/// Position (mm) and angle (deg) of each pose from `centre`.
void Deviations(std::span<const Rigid3d> poses, const Rigid3d& centre, std::vector<double>& mm, std::vector<double>& deg) {
  mm.clear(), deg.clear();
  for (const Rigid3d& pose : poses) {
    mm.push_back(1000.0 * TranslationDistanceM(pose, centre));
    deg.push_back(RotationDistanceDeg(pose, centre));
  }
}

double Rms(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x * x;
  return v.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(v.size()));
}

}  // namespace

void ObjectMountOptions::check() const {
  if (min_records < 3) throw InputError("ObjectMountOptions.min_records", Str("is ", min_records, "; need >= 3"));
  if (!(outlier_sigmas > 0)) throw InputError("ObjectMountOptions.outlier_sigmas", "must be positive");
  if (!(min_outlier_mm > 0)) throw InputError("ObjectMountOptions.min_outlier_mm", "must be positive");
  if (!(min_outlier_deg > 0)) throw InputError("ObjectMountOptions.min_outlier_deg", "must be positive");
}

std::vector<int> InlierPoses(std::span<const Rigid3d> poses, double sigmas, double min_mm, double min_deg) {
  // A centre that outliers cannot pull (a mean can be): the component-wise median of the translations
  // and of the rotation vectors about a first average rotation (small spreads: the log map is linear).
  const Rigid3d first = AveragePoses(poses);
  std::vector<double> comp[6];
  for (const Rigid3d& pose : poses) {
    const Eigen::Vector3d r = (first.inverse() * pose).rvec();
    for (int i = 0; i < 3; ++i) comp[i].push_back(r[i]), comp[3 + i].push_back(pose.translation()[i]);
  }
  const Rigid3d centre(first.rotation() * Rigid3d::FromRvec(Eigen::Vector3d(Median(comp[0]), Median(comp[1]), Median(comp[2])),
                                                            Eigen::Vector3d::Zero()).rotation(),
                       Eigen::Vector3d(Median(comp[3]), Median(comp[4]), Median(comp[5])));
  std::vector<double> mm, deg;
  Deviations(poses, centre, mm, deg);
  // Deviations are distances (non-negative): their median is the robust scale, 1.4826 makes it a sigma
  // for a normal component; the bound is measured from 0, not from the median.
  const double bound_mm = std::max(min_mm, sigmas * 1.4826 * Median(mm));
  const double bound_deg = std::max(min_deg, sigmas * 1.4826 * Median(deg));
  std::vector<int> kept;
  for (size_t i = 0; i < poses.size(); ++i)
    if (mm[i] <= bound_mm && deg[i] <= bound_deg) kept.push_back(static_cast<int>(i));
  return kept;
}

ObjectMountResult EstimateObjectMount(std::span<const LabelEstimatePair> pairs, const Rigid3d& T_objbody_mesh_current,
                                      const ObjectMountOptions& options) {
  options.check();
  std::vector<Rigid3d> estimates;
  estimates.reserve(pairs.size());
  for (const LabelEstimatePair& p : pairs)
    estimates.push_back(T_objbody_mesh_current * p.T_camera_mesh_label.inverse() * p.T_camera_mesh_segicp);
  if (static_cast<int>(estimates.size()) < options.min_records)
    throw InputError("object mount", Str("too few records: ", estimates.size(), " reliable (need ", options.min_records,
                                         "); validate more frames in which the object is well seen"));
  const std::vector<int> kept = InlierPoses(estimates, options.outlier_sigmas, options.min_outlier_mm, options.min_outlier_deg);
  if (static_cast<int>(kept.size()) < options.min_records)
    throw InputError("object mount", Str("too few records: ", kept.size(), " of ", estimates.size(),
                                         " agree with each other (need ", options.min_records, ")"));
  std::vector<Rigid3d> used;
  for (int i : kept) used.push_back(estimates[static_cast<size_t>(i)]);
  ObjectMountResult result;
  result.T_objbody_mesh = AveragePoses(used);
  result.correction = T_objbody_mesh_current.inverse() * result.T_objbody_mesh;
  result.records_used = static_cast<int>(used.size());
  result.records_dropped = static_cast<int>(estimates.size() - used.size());
  std::vector<double> mm, deg;
  Deviations(used, result.T_objbody_mesh, mm, deg);
  result.spread_mm = Rms(mm), result.spread_deg = Rms(deg);
  // The interval of the mean per axis, from the signed deviations along each axis; the largest of the
  // three (translation, mm) and of the three rotation-vector components (deg) is reported.
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> dt, dr;
    for (const Rigid3d& u : used) {
      const Rigid3d d = result.T_objbody_mesh.inverse() * u;
      dt.push_back(1000.0 * d.translation()[axis]);
      dr.push_back(DegFromRad(d.rvec()[axis]));
    }
    double rho_t = 0, rho_r = 0;
    result.ci95_mm = std::max(result.ci95_mm, MeanInterval95(dt, rho_t));
    result.ci95_deg = std::max(result.ci95_deg, MeanInterval95(dr, rho_r));
    result.autocorrelation = std::max({result.autocorrelation, rho_t, rho_r});
  }
  if (result.records_dropped * 4 > static_cast<int>(estimates.size()))
    result.warnings.push_back(Str(result.records_dropped, " of ", estimates.size(),
                                  " records disagree with the rest: check the object's depth in those frames (occlusion, range)"));
  return result;
}

}  // namespace mocap
