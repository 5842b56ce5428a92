#pragma once
// The protocol side of the tracker emulator, free of I/O: takes one command line, returns the reply
// bytes a Polaris/Vega would send (same framing, CRCs, BX/TX layout and ERRORxx codes as
// reference ndi-combined-api.md). One instance per connection; the bodies come from a TrajectorySource.
#include <cstdint>
#include <map>
#include <memory>
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
  void check() const;
};

/// The reply to one command.
struct EmulatorReply {
  std::string bytes{};
  bool tracking_data = false;      ///< BX/TX data (latency and corruption apply to these)
  TrackingReply served{};          ///< what the BX/TX reply carries, when tracking_data
  int new_baud = 0;                ///< COMM acknowledged: the line switches to this baud after the reply
};

class EmulatedTracker {
 public:
  EmulatedTracker(EmulatedTrackerOptions options, std::shared_ptr<const TrajectorySource> trajectory);

  /// One command as received, without or with its trailing CR. `t_s`: seconds since tracking started
  /// (selects the frame).
  EmulatorReply Handle(std::string_view line, double t_s);

  /// Frame number at `t_s`, and the time of a frame.
  uint32_t FrameAt(double t_s) const;
  double TimeOfFrame(uint32_t frame) const;
  /// What BX reports for `body` in `frame` (noise, dropout and volume applied).
  HandleReport Report(int body, uint32_t frame, uint16_t options) const;

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
};

}  // namespace mocap::ndi
