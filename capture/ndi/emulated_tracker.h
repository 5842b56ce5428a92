#pragma once
// The protocol side of the tracker emulator, free of I/O: takes one command line, returns the reply
// bytes a Polaris/Vega would send (same framing, CRCs, BX/TX layout and ERRORxx codes as
// reference ndi-combined-api.md). One instance per connection; the bodies come from a TrajectorySource.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "capture/ndi/reply.h"
#include "capture/ndi/trajectory.h"

namespace mocap::ndi {

struct EmulatedTrackerOptions {
  double rate_hz = 60;             ///< camera frame rate; frame numbers advance at this rate
  uint32_t first_frame = 1000;     ///< frame number at t = 0
  double noise_mm = 0;             ///< Gaussian noise (sigma, per axis) on positions
  double dropout = 0;              ///< probability that a body is MISSING in a frame
  uint64_t seed = 1;               ///< noise and dropouts are a function of (seed, body, frame)
  std::optional<TrackingVolume> volume{};
  /// Bodies appear as already-present (wired) handles 01, 02, ... after INIT; otherwise only through
  /// PHRQ + PVWR (passive tools). Either way PHRQ binds the next body whose handle is not yet initialised.
  bool preloaded_handles = true;
  /// Tracking time 0 is a client's TSTART (TrackingClock: `mocaplabel ndi-emulator`), so a client that
  /// connects late still hears a replay from its start; otherwise it is the `t_s` the caller passes
  /// (the emulator's start: in-process users sharing that clock, `capture replay`).
  bool clock_from_tstart = false;
  /// Markers of each tool, reported with BX option 0x0008 (3D marker positions): all of them while the
  /// tool is VALID, none while it is MISSING (a tracker that sees too few markers cannot fit the tool).
  int markers_per_tool = 4;
  void check() const;
};

/// Tracking time of clock_from_tstart, shared by an emulator's connections: a TSTART starts it when it
/// is not running, a TSTOP stops it (the next TSTART starts from 0 again). A client that loses its
/// connection and comes back (INIT, TSTART, no TSTOP) continues it, so frame numbers go on. Thread-safe.
class TrackingClock {
 public:
  void Start(double t_s);
  void Stop();
  /// Seconds since the start at caller time `t_s`; 0 when not running.
  double Since(double t_s) const;

 private:
  mutable std::mutex mutex_;
  std::optional<double> start_s_;
};

/// The reply to one command.
struct EmulatorReply {
  std::string bytes{};
  bool tracking_data = false;      ///< BX/TX data (latency and corruption apply to these)
  TrackingReply served{};          ///< what the BX/TX reply carries, when tracking_data
  int new_baud = 0;                ///< COMM acknowledged: the line switches to this baud after the reply
  bool past_end = false;           ///< BX/TX for a time after the trajectory's end (a replay ran out)
};

class EmulatedTracker {
 public:
  /// `clock`: the emulator's shared tracking clock (clock_from_tstart); null: one of its own.
  EmulatedTracker(EmulatedTrackerOptions options, std::shared_ptr<const TrajectorySource> trajectory,
                  std::shared_ptr<TrackingClock> clock = nullptr);

  /// One command as received, without or with its trailing CR. `t_s`: seconds on the caller's clock
  /// (the emulator's start); with clock_from_tstart the frame is chosen by the time since TSTART.
  EmulatorReply Handle(std::string_view line, double t_s);
  /// Tracking time at `t_s` on the caller's clock (with clock_from_tstart: since the TSTART that
  /// started the clock, 0 while it is stopped).
  double TrackingTime(double t_s) const;

  /// Frame number at `t_s`, and the time of a frame.
  uint32_t FrameAt(double t_s) const;
  double TimeOfFrame(uint32_t frame) const;
  /// What BX reports for `body` in `frame` (noise, dropout and volume applied).
  HandleReport Report(int body, uint32_t frame, uint16_t options) const;
  std::vector<std::array<double, 3>> MarkersMm(const Rigid3d& T_tracker_body, const Eigen::Vector3d& t_mm) const;

 private:
  struct PortHandle {
    int body = -1;                 ///< index into the trajectory, -1 for none
    bool from_phrq = false;
    bool rom_written = false;
    bool initialised = false;
    bool enabled = false;
  };
  using Params = std::string_view;
  std::string Dispatch(std::string_view name, Params params, double t_s, EmulatorReply& reply);
  std::string Phsr(Params params);
  std::string Phrq(Params params);
  std::string Pvwr(Params params);
  std::string HandleCommand(std::string_view name, Params params);
  std::string Tracking(std::string_view name, Params params, double t_s, EmulatorReply& reply);
  void Reset();

  EmulatedTrackerOptions options_;
  std::shared_ptr<const TrajectorySource> trajectory_;
  std::map<int, PortHandle> handles_;
  bool initialised_ = false;
  bool tracking_ = false;
  std::shared_ptr<TrackingClock> clock_;
};

}  // namespace mocap::ndi
