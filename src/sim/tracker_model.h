#pragma once
// The simulated tracker: from the true pose of a marker tool, what the tracker reports. Each marker is
// tested for visibility (inside the measurement volume, facing the tracker, line of sight not blocked by
// an occluder), the visible ones are perturbed by isotropic Gaussian noise (per-axis sigma =
// noise_rms_mm / sqrt(3)) and the tool pose is re-fitted to them with the least-squares rigid fit of
// Umeyama (1991) without scale, as the tracker does. Rotation noise therefore follows from the marker
// geometry: small tools and few markers give larger rotation errors.
#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "core/pose_stream.h"
#include "sim/sim_objects.h"
#include "sim/rng.h"
#include "sim/tracker_options.h"

namespace mocap::sim {

/// An oriented box that blocks lines of sight (tracker frame).
struct OccluderBox {
  Rigid3d T_tracker_box;
  Eigen::Vector3d half_extents_m;
  /// True when the segment a-b (tracker frame) passes through the box.
  bool BlocksSegment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
};

struct TrackerMeasurement {
  PoseStatus status = PoseStatus::kMissing;
  Rigid3d T_tracker_body;      ///< the fitted pose when HasPose(status)
  int visible_markers = 0;
  int out_of_volume_markers = 0;
  int facing_away_markers = 0;
  int occluded_markers = 0;
  bool random_dropout = false;
  double fit_rms_m = 0;        ///< RMS marker residual of the fit
};

/// Least-squares rigid transform mapping `model` onto `measured` (Umeyama, no scale).
/// Precondition: same size, at least 3 non-collinear points.
Rigid3d FitRigid(std::span<const Eigen::Vector3d> model, std::span<const Eigen::Vector3d> measured);

/// One tracker sample of one tool at its true pose `T_tracker_body`.
TrackerMeasurement MeasureBody(const MarkerBody& body, const Rigid3d& T_tracker_body,
                               std::span<const OccluderBox> occluders, const TrackerOptions& options, Rng& rng);

/// The samples of one tool, stamped on the host clock (measurement time + latency).
struct BodyStream {
  std::string body;
  std::vector<PoseSample> samples;
  std::vector<TrackerMeasurement> measurements;  ///< diagnostics, one per sample
  std::vector<Rigid3d> true_T_tracker_body;       ///< the truth at each measurement instant
  /// Fraction of samples with a pose.
  double valid_fraction() const;
};

}  // namespace mocap::sim
