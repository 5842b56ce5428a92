#pragma once
// Settings of the simulated optical tracker (an NDI Polaris Vega-like system with passive marker tools).
#include <Eigen/Core>

#include "core/rigid3.h"

namespace mocap::sim {

/// Measurement volume: a truncated pyramid with its apex at the tracker origin, opening along the
/// tracker's -z axis (NDI reports z < 0 in front of the position sensor), x horizontal, y vertical.
/// Defaults approximate the Polaris Vega "pyramid" volume (0.95 m to 2.4 m, 1.566 x 1.312 m at the far
/// plane); they are not taken from an NDI document: set them from the data sheet of your tracker.
struct TrackingVolume {
  double near_m = 0.95;
  double far_m = 2.4;
  double half_width_far_m = 0.783;
  double half_height_far_m = 0.656;
  /// True when `point_tracker_m` (tracker frame, metres) lies inside.
  bool Contains(const Eigen::Vector3d& point_tracker_m) const;
  void check() const;
};

struct TrackerOptions {
  double rate_hz = 60.0;        ///< Vega ST/VT fixed frame rate (ndi-combined-api.md §9)
  /// Delay from the instant the markers are measured to the host receive stamp (Vega: 14.2 +- 1.8 ms).
  double latency_ms = 14.2;
  /// 3D RMS error of one marker position (mm); Vicra/Vega data sheets give <= 0.25 mm.
  double noise_rms_mm = 0.15;
  /// A marker is lost when the angle between its facing direction and the line of sight to the tracker
  /// exceeds this (passive spheres on a planar tool are usable to about 75-80 degrees).
  double max_marker_angle_deg = 75.0;
  int min_markers = 3;               ///< fewer visible markers: the body is missing
  double dropout_probability = 0.0;  ///< chance that a body is missing in a sample for no visible reason
  TrackingVolume volume;
  Rigid3d T_world_tracker;           ///< pose of the tracker (its measurement frame) in the world
  /// Throws InputError naming the field.
  void check() const;
};

}  // namespace mocap::sim
