#pragma once
// Point-to-point ICP (Besl & McKay) with the closed-form SVD step of Umeyama/Kabsch per iteration, the
// registration the paper uses for both acquisition and tracking ("We use a point-to-point ICP").
// One pass per iteration: nearest neighbours are accumulated into first and second moments, no
// correspondence list is stored. Each source point remembers its last search (its match and how far
// that match was proven the only scene point around it), so that a point that has moved less than the
// proof covers keeps its match without a search: exact, and most points of a converging registration.
#include <string_view>

#include "core/rigid3.h"
#include "validate/point_grid.h"
#include "validate/point_cloud.h"

namespace mocap {

struct IcpOptions {
  /// Correspondences farther than this are ignored at the end of the schedule, metres.
  double max_correspondence_distance_m = 0.01;
  /// The gate starts here and shrinks by `gate_shrink` per iteration down to the value above, so a
  /// start several centimetres off is pulled in before the tight gate rejects clutter.
  double initial_correspondence_distance_m = 0.05;
  double gate_shrink = 0.7;
  int max_iterations = 60;
  /// Converged when one update moves less than both of these (and the gate is at its final value).
  double translation_epsilon_m = 1e-4;
  double rotation_epsilon_deg = 0.03;
  /// Coarse-to-fine: iterate on every `source_stride`-th source point until converged, then finish on
  /// all points (performance.md section 2: 1/4 of the points cuts the cost about 4x at equal accuracy).
  int source_stride = 1;
  /// Fewer correspondences than this stops the registration (too little overlap to trust the SVD).
  int min_correspondences = 10;
  /// Besl & McKay's accelerated ICP (validate/icp_acceleration.h) once the gate is at its final value:
  /// point-to-point ICP creeps along planar faces, and extrapolating along a run of aligned updates
  /// reaches the same optimum in fewer iterations. An extrapolated pose whose truncated error (gated
  /// squared distances, gate^2 for points without a correspondence) exceeds that of the pose it came
  /// from is undone.
  bool accelerate = false;
  /// Successive updates within this angle of each other count as aligned (Besl & McKay: 10 deg).
  double acceleration_angle_deg = 10.0;
  /// The longest extrapolation, in lengths of the last update (Besl & McKay: 25).
  double acceleration_max_factor = 25.0;
  /// Throws InputError on non-positive distances, iterations or strides.
  void check() const;
};

enum class IcpStopReason { kConverged, kMaxIterations, kTooFewCorrespondences, kEmptyInput };
std::string_view ToString(IcpStopReason reason);

struct IcpResult {
  Rigid3d T_target_source;     ///< the registration (initial guess when nothing could be done)
  int iterations = 0;          ///< SVD updates made
  double inlier_rmse_m = 0.0;  ///< RMS distance of the correspondences of the last iteration
  double fitness = 0.0;        ///< inliers of the last iteration / source points used
  int num_inliers = 0;
  bool converged = false;
  IcpStopReason reason = IcpStopReason::kEmptyInput;
};

/// Registers `source` (points in the source frame) to the scene indexed by `target`, starting from
/// `T_target_source_init`. Precondition: options.check() passed.
IcpResult AlignPointToPoint(const PointCloud& source, const PointGrid& target, const Rigid3d& T_target_source_init,
                            const IcpOptions& options);

/// The rigid transform minimising sum |R s_i + t - t_i|^2 (Umeyama 1991 without scale), from paired
/// points. Precondition: equal sizes >= 3, not all collinear.
Rigid3d KabschTransform(const PointCloud& source, const PointCloud& target);

}  // namespace mocap
