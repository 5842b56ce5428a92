#include "sim/tracker_model.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/check.h"

namespace mocap::sim {

bool TrackingVolume::Contains(const Eigen::Vector3d& p) const {
  const double depth = -p.z();
  if (depth < near_m || depth > far_m) return false;
  return std::abs(p.x()) <= depth * half_width_far_m / far_m && std::abs(p.y()) <= depth * half_height_far_m / far_m;
}

void TrackingVolume::check() const {
  if (!(near_m > 0 && far_m > near_m)) throw InputError("tracker.volume", "need 0 < near_m < far_m");
  if (!(half_width_far_m > 0 && half_height_far_m > 0)) throw InputError("tracker.volume", "far-plane half sizes must be positive");
}

void TrackerOptions::check() const {
  if (!(rate_hz > 0 && rate_hz <= 1000)) throw InputError("tracker.rate_hz", Str("must be in (0, 1000], got ", rate_hz));
  if (!(latency_ms >= 0 && latency_ms < 1000)) throw InputError("tracker.latency_ms", Str("must be in [0, 1000), got ", latency_ms));
  if (!(noise_rms_mm >= 0 && noise_rms_mm <= 10)) throw InputError("tracker.noise_rms_mm", Str("must be in [0, 10], got ", noise_rms_mm));
  if (!(max_marker_angle_deg > 0 && max_marker_angle_deg <= 90))
    throw InputError("tracker.max_marker_angle_deg", Str("must be in (0, 90], got ", max_marker_angle_deg));
  if (min_markers < 3) throw InputError("tracker.min_markers", "a rigid pose needs at least 3 markers");
  if (!(dropout_probability >= 0 && dropout_probability <= 1)) throw InputError("tracker.dropout_probability", "must be in [0, 1]");
  volume.check();
}

bool OccluderBox::BlocksSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  // Slab test in the box frame.
  const Rigid3d T_box_tracker = T_tracker_box.inverse();
  const Eigen::Vector3d p = T_box_tracker * a;
  const Eigen::Vector3d d = T_box_tracker * b - p;
  double t_min = 0, t_max = 1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-15) {
      if (std::abs(p[k]) > half_extents_m[k]) return false;
      continue;
    }
    double t0 = (-half_extents_m[k] - p[k]) / d[k];
    double t1 = (half_extents_m[k] - p[k]) / d[k];
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
    if (t_min > t_max) return false;
  }
  return true;
}

Rigid3d FitRigid(std::span<const Eigen::Vector3d> model, std::span<const Eigen::Vector3d> measured) {
  MOCAP_CHECK(model.size() == measured.size() && model.size() >= 3, "rigid fit needs 3 matching points");
  Eigen::Matrix3Xd src(3, model.size()), dst(3, measured.size());
  for (size_t i = 0; i < model.size(); ++i) {
    src.col(static_cast<Eigen::Index>(i)) = model[i];
    dst.col(static_cast<Eigen::Index>(i)) = measured[i];
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
  return Rigid3d::FromMatrix4(T);
}

TrackerMeasurement MeasureBody(const MarkerBody& body, const Rigid3d& T_tracker_body,
                               std::span<const OccluderBox> occluders, const TrackerOptions& options, Rng& rng) {
  TrackerMeasurement m;
  const double sigma_m = options.noise_rms_mm * 1e-3 / std::sqrt(3.0);
  const double cos_limit = std::cos(RadFromDeg(options.max_marker_angle_deg));
  const Eigen::Vector3d normal_tracker = T_tracker_body.rotation() * body.normal_body;
  std::vector<Eigen::Vector3d> model, measured;
  for (const Eigen::Vector3d& marker_body : body.markers_m) {
    const Eigen::Vector3d marker = T_tracker_body * marker_body;
    // Draw the noise for every marker so the random sequence does not depend on visibility.
    const Eigen::Vector3d noise(rng.Normal(sigma_m), rng.Normal(sigma_m), rng.Normal(sigma_m));
    if (!options.volume.Contains(marker)) {
      ++m.out_of_volume_markers;
      continue;
    }
    if (normal_tracker.dot(-marker.normalized()) < cos_limit) {
      ++m.facing_away_markers;
      continue;
    }
    const bool blocked = std::any_of(occluders.begin(), occluders.end(),
                                     [&](const OccluderBox& box) { return box.BlocksSegment(marker, Eigen::Vector3d::Zero()); });
    if (blocked) {
      ++m.occluded_markers;
      continue;
    }
    model.push_back(marker_body);
    measured.push_back(marker + noise);
  }
  m.visible_markers = static_cast<int>(model.size());
  m.random_dropout = rng.Bernoulli(options.dropout_probability);
  const int markers = static_cast<int>(body.markers_m.size());
  if (m.out_of_volume_markers == markers) {
    m.status = PoseStatus::kOutOfVolume;
  } else if (m.visible_markers < options.min_markers || m.random_dropout) {
    m.status = PoseStatus::kMissing;
  } else {
    m.T_tracker_body = FitRigid(model, measured);
    double sum_sq = 0;
    for (size_t i = 0; i < model.size(); ++i) sum_sq += (m.T_tracker_body * model[i] - measured[i]).squaredNorm();
    m.fit_rms_m = std::sqrt(sum_sq / static_cast<double>(model.size()));
    m.status = m.out_of_volume_markers > 0 ? PoseStatus::kPartiallyInVolume : PoseStatus::kValid;
  }
  return m;
}

double BodyStream::valid_fraction() const {
  if (samples.empty()) return 0;
  const auto valid = std::count_if(samples.begin(), samples.end(), [](const PoseSample& s) { return HasPose(s.status); });
  return static_cast<double>(valid) / static_cast<double>(samples.size());
}

}  // namespace mocap::sim
