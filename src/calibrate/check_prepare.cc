#include "calibrate/check_model.h"
#include "calibrate/robust_stats.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace mocap::check_model {
namespace {

int IndexOf(std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it != names.end()) return static_cast<int>(it - names.begin());
  names.push_back(name);
  return static_cast<int>(names.size()) - 1;
}

Eigen::Matrix3d Hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// The projection of a residual [a; d] (camera frame: a turn a, the mesh origin moved by d) onto the
/// judged directions. A point x of the mesh moves by a x (R x) + d, so in analysis coordinates the
/// residual is u = [L R^T a; R^T (d - (R c) x a)]; its judged part u' = B B^T u is taken back by the
/// inverse map a = R u'_w / L, d = R u'_v + (R c) x a.
Eigen::Matrix<double, 6, 6> JudgedPart(const CheckRecord::Judged& judged, const Eigen::Matrix3d& R) {
  const double L = judged.radius_m;
  const Eigen::Matrix3d C = Hat(R * judged.center_mesh);
  Eigen::Matrix<double, 6, 6> to = Eigen::Matrix<double, 6, 6>::Zero(), from = Eigen::Matrix<double, 6, 6>::Zero();
  to.topLeftCorner<3, 3>() = L * R.transpose();
  to.bottomLeftCorner<3, 3>() = -R.transpose() * C;
  to.bottomRightCorner<3, 3>() = R.transpose();
  from.topLeftCorner<3, 3>() = R / L;
  from.bottomLeftCorner<3, 3>() = C * R / L;
  from.bottomRightCorner<3, 3>() = R;
  return from * judged.directions * judged.directions.transpose() * to;
}

Prepared BuildIndex(std::span<const CheckRecord> records) {
  Prepared index;
  std::vector<ModelRecord>& model = index.records;
  std::map<std::pair<std::string, int>, std::vector<int>> tracks;
  for (size_t i = 0; i < records.size(); ++i) {
    const CheckRecord& r = records[i];
    ModelRecord m;
    m.camera = IndexOf(index.cameras, r.camera), m.object = IndexOf(index.objects, r.object);
    m.q_label = r.T_camera_mesh_label.rotation(), m.q_segicp = r.T_camera_mesh_segicp.rotation();
    if (m.q_label.dot(m.q_segicp) < 0) m.q_segicp.coeffs() *= -1;
    m.p_label_m = r.T_camera_mesh_label.translation(), m.p_segicp_m = r.T_camera_mesh_segicp.translation();
    if (r.spin_axis_mesh.norm() > 0) m.spin_axis_camera = r.T_camera_mesh_label.rotation() * r.spin_axis_mesh.normalized();
    if (r.judged) m.judged_part = JudgedPart(*r.judged, r.T_camera_mesh_label.rotation_matrix());
    model.push_back(m);
    tracks[{r.camera, r.instance}].push_back(static_cast<int>(i));
  }
  for (auto& [key, track] : tracks) {
    std::stable_sort(track.begin(), track.end(), [&](int a, int b) { return records[a].stamp_ns < records[b].stamp_ns; });
    index.tracks.push_back(track);
  }
  return index;
}

/// Central (or one-sided) differences of the labels along each track, where neighbours are close.
void SetVelocities(std::span<const CheckRecord> records, const Prepared& index, int64_t max_gap_ns, std::vector<ModelRecord>& model) {
  for (const std::vector<int>& track : index.tracks)
    for (size_t j = 0; j < track.size(); ++j) {
      const CheckRecord& here = records[track[j]];
      size_t a = j, b = j;
      if (j > 0 && here.stamp_ns - records[track[j - 1]].stamp_ns <= max_gap_ns) a = j - 1;
      if (j + 1 < track.size() && records[track[j + 1]].stamp_ns - here.stamp_ns <= max_gap_ns) b = j + 1;
      if (a == b) continue;
      const Rigid3d& La = records[track[a]].T_camera_mesh_label;
      const Rigid3d& Lb = records[track[b]].T_camera_mesh_label;
      const double dt_s = 1e-9 * static_cast<double>(records[track[b]].stamp_ns - records[track[a]].stamp_ns);
      if (!(dt_s > 0)) continue;
      ModelRecord& m = model[static_cast<size_t>(track[j])];
      m.v_m_per_s = (Lb.translation() - La.translation()) / dt_s;
      m.w_rad_per_s = (Lb * La.inverse()).rvec() / dt_s;
      m.has_motion = true;
    }
}

/// Each object's residual scales with no item applied: 1.4826 MAD about the median, per component.
void SetScales(const Prepared& index, const CalibrationCheckOptions& options, std::vector<ModelRecord>& model) {
  Params zero;
  zero.camera.assign(index.cameras.size(), {0, 0, 0, 0, 0, 0});
  zero.object.assign(index.objects.size(), {0, 0, 0, 0, 0, 0});
  for (int k = 0; k < static_cast<int>(index.objects.size()); ++k) {
    std::vector<std::vector<double>> comp(6);
    for (const ModelRecord& m : model)
      if (m.object == k) {
        const Eigen::Matrix<double, 6, 1> e = Residual(m, zero);
        for (int i = 0; i < 6; ++i) comp[static_cast<size_t>(i)].push_back(e(i));
      }
    double mad_rad = 0, mad_m = 0;
    for (int i = 0; i < 6; ++i) {
      std::vector<double>& c = comp[static_cast<size_t>(i)];
      const double median = Median(c);
      for (double& x : c) x = std::abs(x - median);
      (i < 3 ? mad_rad : mad_m) += 1.4826 * Median(c) / 3;
    }
    for (ModelRecord& m : model)
      if (m.object == k) {
        m.sigma_rad = std::max(RadFromDeg(options.min_sigma_deg), mad_rad);
        m.sigma_m = std::max(1e-3 * options.min_sigma_mm, mad_m);
      }
  }
}

}  // namespace

/// Lag-1 autocorrelation of the scaled residual components along the tracks, clamped to [0, 0.95].
double ResidualAutocorrelation(const Prepared& prepared, const Params& params) {
  const Prepared& index = prepared;
  const std::vector<ModelRecord>& model = prepared.records;
  double var = 0, cov = 0;
  for (const std::vector<int>& track : index.tracks) {
    Eigen::Matrix<double, 6, 1> previous = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t j = 0; j < track.size(); ++j) {
      const ModelRecord& m = model[static_cast<size_t>(track[j])];
      Eigen::Matrix<double, 6, 1> e = Residual(m, params);
      e.head<3>() /= m.sigma_rad, e.tail<3>() /= m.sigma_m;
      var += e.squaredNorm();
      if (j > 0) cov += e.dot(previous);
      previous = e;
    }
  }
  return var > 0 ? std::clamp(cov / var, 0.0, 0.95) : 0.0;
}

Prepared Prepare(std::span<const CheckRecord> records, const CalibrationCheckOptions& options) {
  Prepared prepared = BuildIndex(records);
  SetVelocities(records, prepared, options.max_neighbour_gap_ns, prepared.records);
  SetScales(prepared, options, prepared.records);
  return prepared;
}

}  // namespace mocap::check_model
