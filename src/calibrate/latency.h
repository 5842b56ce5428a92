#pragma once
// Tracker-to-camera latency from one recording of the board moving relative to the camera.
//
// Convention (the rig's tracker_latency_ns, docs/rig.md): a camera frame stamped t shows the scene the
// tracker reports at t + latency (positive when the tracker's stamps lag the camera's).
//
// Signal: how far the board turns relative to the camera between two frames about pair_interval_ns
// apart. From the images it is the angle of inv(T_camera_board(t_a)) * T_camera_board(t_b); from the
// tracker it is the angle of inv(T_cambody_boardbody(t_a + L)) * T_cambody_boardbody(t_b + L). Both
// are the same rotation conjugated by a mount (inv(T_boardbody_board) ... T_boardbody_board), so their
// angles agree for the right L whatever the mounts are: no camera-mount calibration is needed first.
// Cost(L) = RMS over the pairs of the angle difference; a coarse grid over +-search_half_range_ns,
// then golden-section search in the best grid cell down to tolerance_ns.
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/pose_stream.h"
#include "core/rigid3.h"

namespace mocap {

/// T_camera_board from the frame stamped stamp_ns (e.g. EstimateBoardPose on its detection).
struct StampedBoardPose {
  int64_t stamp_ns = 0;
  Rigid3d T_camera_board;
};

/// The tracked relative pose T_cambody_boardbody at a tracker stamp; empty where the tracker has none.
using RelativePoseAt = std::function<std::optional<Rigid3d>(int64_t tracker_stamp_ns)>;

/// inv(T_tracker_cambody(t)) * T_tracker_boardbody(t), both interpolated (InterpolatePose); empty when
/// either lookup fails. The streams are copied into the callable; each must be sorted by stamp.
RelativePoseAt RelativePoseFromStreams(std::vector<PoseSample> cambody, std::vector<PoseSample> boardbody,
                                       const InterpolationOptions& interpolation = {});

struct LatencyOptions {
  int64_t search_half_range_ns = 200'000'000;  ///< latencies searched: +-this
  int64_t coarse_step_ns = 2'000'000;          ///< grid step of the first pass
  int64_t pair_interval_ns = 100'000'000;      ///< frames compared are at least this far apart
  int64_t tolerance_ns = 20'000;               ///< golden-section search stops below this bracket
  int min_pairs = 30;                          ///< frame pairs needed with tracker data over the whole range
  double min_contrast = 3.0;                   ///< median grid cost / best cost below this: a warning
  double min_turn_deg = 3.0;                   ///< RMS image turn per pair below this: a warning (too slow)
  /// Throws InputError naming the field.
  void check() const;
};

struct LatencyResult {
  int64_t tracker_latency_ns = 0;
  double rms_deg = 0;       ///< angle disagreement at the optimum
  double contrast = 0;      ///< median coarse cost / best cost: how distinct the minimum is
  double turn_rms_deg = 0;  ///< RMS of the image-derived turn per pair: how much the board moved
  int pairs_used = 0;
  std::vector<std::pair<int64_t, double>> coarse_cost_deg;  ///< (latency ns, RMS deg) of the grid
  std::vector<std::string> warnings;  ///< each says what to record instead
};

/// Estimates the latency. Precondition: image_poses sorted by stamp. Throws InputError for invalid
/// options or when fewer than min_pairs frame pairs have tracker data at every latency searched.
LatencyResult EstimateTrackerLatency(std::span<const StampedBoardPose> image_poses, const RelativePoseAt& T_cambody_boardbody_at,
                                     const LatencyOptions& options = {});

}  // namespace mocap
