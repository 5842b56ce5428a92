#pragma once
// The NDI tracker emulator: serves EmulatedTracker over TCP on loopback (as a Vega on port 8765) or
// over any file descriptor (a pseudo-terminal master for the serial path), with injected faults:
// reply latency and corrupted bytes on tracking replies (noise and dropouts come from the tracker
// model). `mocaplabel ndi-emulator` runs one; tests start one in process on an ephemeral port.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "capture/ndi/emulated_tracker.h"
#include "capture/ndi/trajectory.h"

namespace mocap::ndi {

struct EmulatorOptions {
  std::string bind = "127.0.0.1";  ///< listen address; anything but loopback is the caller's choice
  int port = 8765;                  ///< 0: an ephemeral port (see Emulator::port())
  double latency_ms = 0;            ///< delay before each BX/TX reply
  double corrupt = 0;               ///< probability that a BX/TX reply gets one byte flipped
  EmulatedTrackerOptions tracker{};
  /// Log (warning) the first reply of each connection past the trajectory's end (a replay that ran
  /// out): `mocaplabel ndi-emulator`. Off for in-process replays whose end is planned (`capture replay`).
  bool log_replay_end = false;
  void check() const;
};

struct EmulatorStats {
  uint64_t connections = 0;
  uint64_t commands = 0;
  uint64_t tracking_replies = 0;
  uint64_t error_replies = 0;
  uint64_t corrupted_replies = 0;
  uint64_t past_end_replies = 0;    ///< BX/TX after the trajectory's end (a replay that ran out)
  int last_baud = 9600;             ///< last baud rate acknowledged with COMM
};

class Emulator {
 public:
  Emulator(EmulatorOptions options, std::shared_ptr<const TrajectorySource> trajectory);
  ~Emulator();
  Emulator(const Emulator&) = delete;
  Emulator& operator=(const Emulator&) = delete;

  /// Called (on a serving thread) with the content of every BX/TX reply sent, and whether a byte of
  /// it was then corrupted: the ground truth of what a client received. Set before Start/ServeFd.
  using ServedCallback = std::function<void(const TrackingReply& reply, bool corrupted)>;
  void SetServedCallback(ServedCallback callback) { on_served_ = std::move(callback); }

  /// Binds and listens; throws InputError when the address cannot be bound. The emulator's clock starts
  /// now; tracking time is this clock, or the time since a client's TSTART (clock_from_tstart:
  /// TrackingClock, shared by all connections).
  void Start();
  /// Serves the tracker on `fd` (e.g. a pty master; not owned, not closed) on its own thread until
  /// Stop(). A hang-up on the other side (the pty slave closed) is waited out, not an end.
  void ServeFd(int fd);
  /// Closes the listener and every connection, joins the threads. Idempotent.
  void Stop();

  int port() const { return port_; }
  EmulatorStats stats() const;
  /// Seconds since Start() (or since construction, when only ServeFd is used).
  double Elapsed() const;
  /// CLOCK_MONOTONIC time (ns) of tracking time 0, the origin of Elapsed().
  int64_t start_ns() const { return start_ns_; }
  /// The tracker model of this emulator (for ground truth in tests: FrameAt, TimeOfFrame, Report).
  const EmulatedTracker& model() const { return model_; }

 private:
  void AcceptLoop();
  void Serve(int fd, bool is_socket);
  void Reply(int fd, EmulatorReply reply, uint64_t& rng_state);
  void NotePastEnd(const EmulatorReply& reply, bool& logged) const;

  EmulatorOptions options_;
  std::shared_ptr<const TrajectorySource> trajectory_;
  EmulatedTracker model_;
  std::shared_ptr<TrackingClock> clock_ = std::make_shared<TrackingClock>();  ///< of every connection
  ServedCallback on_served_;
  int64_t start_ns_ = 0;
  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // guards stats_, threads_, connection_fds_
  EmulatorStats stats_;
  std::vector<std::thread> threads_;
  std::vector<int> connection_fds_;
};

}  // namespace mocap::ndi
