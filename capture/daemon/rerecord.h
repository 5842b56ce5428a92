#pragma once
// Re-records a session through the capture daemon in real time (docs/capture.md "Re-recording a
// session"): the recording's tracker stream is served by an NDI emulator on loopback and read back by
// the daemon's NDI source (BX over TCP, as from a Vega), its camera stream is replayed by a session
// replay source, and CaptureDaemon writes a new session between StartSession and StopSession. The
// simulated rig's demo records this way (`mocaplabel demo`), so its session comes out of the same queues,
// writer threads and NDI client as a live one.
//
// Timing: the emulator's tracking time 0 and the camera replay share one host-clock origin
// (lead_in_s after the emulator starts), so camera and tracker keep the recording's relative timing.
// What the path adds is what a live tracker link adds: a sample is stamped when the poll that first
// sees its frame returns, 0 to 1/poll_rate_hz after the frame (docs/capture.md gives the figures).
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "capture/daemon/recorder.h"

namespace mocap::capture {

struct RerecordOptions {
  std::filesystem::path source_session;  ///< a readable session with one camera and one tracker stream
  std::filesystem::path out_session;     ///< the new session folder; must not exist
  double tracker_rate_hz = 0;  ///< the emulated tracker's frame rate; 0 = the recording's (from its stamps)
  double poll_factor = 8;      ///< the NDI client polls BX this many times per tracker frame
  double lead_in_s = 1.0;      ///< emulator start to the first replayed sample: connect, INIT, tools, TSTART
  double tail_s = 0.3;         ///< recorded after the last replayed item, before stopping
  /// A machine too busy to replay in real time hands frames over late (each keeps its due stamp); the
  /// session is stopped at most this long after its scheduled end, so late frames still get in.
  double max_overrun_s = 60;
  RecorderOptions recorder{};  ///< session_dir is out_session
  void check() const;          ///< throws InputError
};

struct RerecordResult {
  nlohmann::json summary;       ///< the daemon's StopSession summary (streams, drops, complete, error)
  nlohmann::json camera;        ///< the replay source's device_status (replayed, skipped, late_frames, max_late_ms)
  nlohmann::json tracker;       ///< the NDI source's device_status (replies, samples, CRC errors, ...)
  int64_t source_frames = 0;    ///< camera records in the source session
  int64_t recorded_frames = 0;  ///< camera records written to the new session
  int64_t dropped_frames = 0;   ///< source frames missing from the new session (drops, late start, errors)
  double tracker_rate_hz = 0, poll_rate_hz = 0;
  double seconds = 0;
  bool complete = false;        ///< the new session closed cleanly and holds every source frame
};

/// Plays `source_session` through the daemon into `out_session`; takes about the recording's duration
/// plus lead_in_s + tail_s. Throws InputError for bad options or an unusable source session and
/// DeviceError when the emulator or the daemon's sources cannot start; recording problems (drops, a
/// write error) are in the result.
RerecordResult RerecordSession(const RerecordOptions& options);

}  // namespace mocap::capture
