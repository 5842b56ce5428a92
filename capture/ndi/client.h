#pragma once
// NDI Combined API tracker client (reference ndi-combined-api.md §4): connects over TCP or serial,
// initialises, loads tools, tracks, polls BX (or TX) at the tracker's rate on its own thread, and
// delivers samples and events through callbacks. A dropped connection is retried with exponential
// backoff; the gap is reported as an event once samples flow again.
//
// Rates (§9): Vega ST/VT 60 Hz, Vega XT up to 400 Hz, Spectra ~60 Hz, Vicra ~20 Hz. Polling faster
// than the camera repeats frames; with skip_repeated_frames (default) a sample is delivered only
// when the device frame number changed.
//
// States (as libfreenect2): Created -> Open (connected, initialised, tools enabled) -> Streaming
// (tracking, polling thread running) -> Closed. Close() may be called in any state.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "capture/ndi/commands.h"
#include "capture/ndi/link.h"
#include "capture/ndi/reply.h"
#include "core/pose_stream.h"
#include "core/rigid3.h"

namespace mocap::ndi {

/// A tool to load. With a .rom path the definition is uploaded (PHRQ + PVWR); without one, the
/// handle the tracker already has (a wired tool) is used, in the order PHSR lists them.
struct ToolSpec {
  std::string name{};    ///< the body name samples carry
  std::string rom_path{};  ///< NDI tool definition file; empty for an already-present handle
  ToolMode mode = ToolMode::kDynamic;
};

struct NdiClientOptions {
  enum class TransportKind { kTcp, kSerial };
  TransportKind transport = TransportKind::kTcp;
  std::string host = "127.0.0.1";
  int port = 8765;                 ///< Vega API port (8764 is TLS, not supported)
  std::string serial_device{};     ///< e.g. /dev/ttyUSB0
  int serial_baud = 115200;        ///< switched to with COMM after INIT at 9600
  std::vector<ToolSpec> tools{};   ///< empty: every handle the tracker reports, named "handle-0A"
  double poll_rate_hz = 60;        ///< the tracker's reporting rate
  bool use_bx = true;              ///< binary BX; false: ASCII TX (fallback for old firmware)
  uint16_t reply_options = 0x0801; ///< transforms + status, also out of volume
  /// With BX, also ask for each tool's 3D marker positions (option 0x0008), for the markers each tool
  /// was fitted from (BodySample::markers). TX has no such option.
  bool request_markers = true;
  bool skip_repeated_frames = true;
  int connect_timeout_ms = 2000;
  int init_timeout_ms = 5000;      ///< first INIT over TCP may take up to 5 s (PlusLib)
  int serial_probe_timeout_ms = 100; ///< serial INIT at 9600 before falling back to a BREAK (ndicapi)
  int reply_timeout_ms = 500;
  int lost_after_failures = 5;     ///< consecutive failed polls that count as a lost connection
  int reconnect_initial_ms = 100;  ///< backoff doubles from this ...
  int reconnect_max_ms = 2000;     ///< ... up to this
  /// Throws InputError naming the bad field.
  void check() const;
};

/// One body in one tracker reply.
struct BodySample {
  std::string name;
  int handle = 0;
  PoseStatus status = PoseStatus::kMissing;
  HandleStatus ndi_status = HandleStatus::kMissing;
  uint32_t frame_number = 0;      ///< device frame counter (0 when DISABLED: not reported)
  uint32_t port_status = 0;       ///< raw port-status bits (reply.h port_status)
  Rigid3d T_tracker_body;         ///< metres; meaningful when has_pose
  bool has_pose = false;          ///< a transform came (also for out of volume)
  double rms_error_m = 0;
  int markers = -1;               ///< markers the tracker measured on the tool (BX 0x0008); -1: not asked
};

/// One BX/TX reply: every body, one host receive time.
struct TrackerSample {
  int64_t host_stamp_ns = 0;      ///< CLOCK_MONOTONIC right after the reply arrived
  uint16_t system_status = 0;     ///< raw bits (reply.h system_status)
  std::vector<BodySample> bodies;
};

/// The body's entry for a core PoseStream (host receive time, status, T_tracker_body).
inline PoseSample ToPoseSample(const TrackerSample& sample, const BodySample& body) {
  return {sample.host_stamp_ns, body.status, body.T_tracker_body};
}

enum class TrackerEventKind {
  kConnected,      ///< setup done, tracking
  kDisconnected,   ///< connection lost; reconnecting
  kReconnected,    ///< setup done again after a loss
  kGap,            ///< first sample after a reconnect: gap_ns, frames before/after
  kReplyError,     ///< a damaged or missing reply (CRC, malformed, timeout), streaming continues
  kDeviceError,    ///< the tracker answered ERRORxx to a poll
  kSystemStatus,   ///< system status bits changed
};
std::string_view ToString(TrackerEventKind kind);

struct TrackerEvent {
  TrackerEventKind kind = TrackerEventKind::kConnected;
  int64_t host_stamp_ns = 0;
  std::string message;
  int64_t gap_ns = 0;             ///< kGap: last sample before the loss to the first after
  uint32_t last_frame_before = 0; ///< kGap
  uint32_t first_frame_after = 0; ///< kGap
};

struct NdiClientStats {
  uint64_t replies = 0;           ///< tracking replies parsed
  uint64_t samples = 0;           ///< samples delivered
  uint64_t repeated_frames = 0;   ///< replies skipped as repeats
  uint64_t crc_errors = 0;
  uint64_t malformed_replies = 0;
  uint64_t timeouts = 0;
  uint64_t device_errors = 0;
  uint64_t disconnects = 0;
  uint64_t reconnects = 0;
};

class NdiClient {
 public:
  enum class State { kCreated, kOpen, kStreaming, kClosed };
  /// Called on the client's polling thread; keep them short (hand off into a queue), and do not call
  /// Close() from them (it joins that thread).
  using SampleCallback = std::function<void(const TrackerSample&)>;
  using EventCallback = std::function<void(const TrackerEvent&)>;

  NdiClient(NdiClientOptions options, SampleCallback on_sample, EventCallback on_event);
  ~NdiClient();
  NdiClient(const NdiClient&) = delete;
  NdiClient& operator=(const NdiClient&) = delete;

  /// Connects, INIT (serial: COMM to serial_baud), loads and enables the tools. Throws
  /// TransportError (cannot connect), ReplyError (the tracker refused, with its ERROR text) or
  /// InputError (a .rom file cannot be read). Created -> Open.
  void Open();
  /// TSTART and the polling thread. Open -> Streaming.
  void StartStreaming();
  /// Stops polling, TSTOP, COMM:00000 on serial, closes. Any state -> Closed. While a reconnect
  /// attempt is under way this waits for it (at most connect_timeout_ms + init_timeout_ms).
  void Close();

  State state() const { return state_.load(); }
  NdiClientStats stats() const;
  /// The handles in use, in tool order, with their names.
  std::vector<std::pair<int, std::string>> handles() const;
  /// Seconds between polls (1 / poll_rate_hz).
  double poll_period_s() const { return 1.0 / options_.poll_rate_hz; }

 private:
  void Connect();
  void Setup();
  void PollLoop();
  void PollOnce();
  /// The BX reply options asked for: reply_options, with 0x0008 when request_markers.
  uint16_t BxOptions() const {
    return static_cast<uint16_t>(options_.reply_options | (options_.request_markers ? reply_option::kToolMarkers : 0));
  }
  void Deliver(const TrackingReply& reply, int64_t stamp_ns);
  void Reconnect();
  void Emit(TrackerEventKind kind, std::string message);
  void SyncCounters();
  void DropLink();  ///< folds the link's counters into folded_ and closes it
  bool SleepFor(int64_t ns);  ///< false when Close() was requested

  NdiClientOptions options_;
  SampleCallback on_sample_;
  EventCallback on_event_;
  std::atomic<State> state_{State::kCreated};
  std::unique_ptr<Link> link_;
  std::vector<std::pair<int, std::string>> handles_;
  std::thread thread_;
  mutable std::mutex mutex_;  // guards stats_, handles_, stop_
  std::condition_variable wake_;
  bool stop_ = false;
  NdiClientStats stats_;
  LinkCounters folded_;        // counters of links already closed
  uint32_t last_frame_ = 0;
  bool have_last_frame_ = false;
  int64_t last_sample_ns_ = 0;
  bool gap_pending_ = false;
  uint16_t last_system_status_ = 0;
};

/// CLOCK_MONOTONIC in nanoseconds.
int64_t MonotonicNowNs();

}  // namespace mocap::ndi
