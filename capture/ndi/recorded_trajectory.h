#pragma once
// A recorded tracker stream served by the emulator (docs/ndi.md "Replaying a recording"): each body's
// samples, with their host stamps and status, played back on the emulator's clock. Trajectory time t
// (seconds since the emulator started tracking) is recording time origin_ns + t. The emulator's frames
// need not fall on the recorded ones: between two usable samples the pose is interpolated (linear
// translation, SLERP rotation: core/pose_stream.h), so every frame reports where the body was at its
// time. A recorded "missing" sample, a gap the interpolation refuses, and any time before the first or
// after the last sample are reported MISSING; out-of-volume and partially-in-volume samples keep their
// pose and set the port-status bits the tracker would (reply.h).
#include <cstdint>
#include <string>
#include <vector>

#include "capture/ndi/trajectory.h"
#include "core/pose_stream.h"

namespace mocap::ndi {

struct RecordedBody {
  std::string name;
  std::vector<PoseSample> samples;  ///< sorted by stamp_ns (recording clock), T_tracker_body in metres
};

struct RecordedTrajectoryOptions {
  int64_t origin_ns = 0;  ///< recording time of trajectory time 0
  /// Longest span between two usable samples that is interpolated (a longer one is a dropout).
  InterpolationOptions interpolation{};
  /// Where interpolation is refused because a neighbour has no usable pose, the nearest recorded pose
  /// is still reported if it is at most this far (ns): about half a tracker frame at 60 Hz.
  int64_t hold_ns = 9'000'000;
  void check() const;  ///< throws InputError
};

class RecordedTrajectory final : public TrajectorySource {
 public:
  /// Throws InputError for an empty body list, an unnamed or duplicated body, or unsorted samples.
  RecordedTrajectory(std::vector<RecordedBody> bodies, const RecordedTrajectoryOptions& options);
  int body_count() const override { return static_cast<int>(bodies_.size()); }
  std::string body_name(int body) const override { return bodies_.at(static_cast<size_t>(body)).name; }
  BodyState At(int body, double t_s) const override;
  /// Tracking time of the last sample: after it every body is MISSING.
  std::optional<double> end_s() const override { return (last_stamp_ns_ - options_.origin_ns) * 1e-9; }
  /// Recording time of the last sample over all bodies (ns).
  int64_t last_stamp_ns() const { return last_stamp_ns_; }

 private:
  std::vector<RecordedBody> bodies_;
  RecordedTrajectoryOptions options_;
  int64_t last_stamp_ns_ = 0;
};

}  // namespace mocap::ndi
