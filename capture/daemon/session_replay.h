#pragma once
// A recorded session played back through the capture pipeline in real time (docs/capture.md
// "Re-recording a session"): its camera stream as a CaptureSource, its tracker stream as the bodies an
// NDI emulator serves (capture/ndi/recorded_trajectory.h). Both map recording time onto the host
// clock by one shared origin, so the pair reproduces the recording's timing between camera and tracker.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capture/daemon/source.h"
#include "capture/ndi/recorded_trajectory.h"
#include "session/reader.h"

namespace mocap::capture {

struct SessionCameraReplayOptions {
  std::filesystem::path session_dir;
  std::string camera;          ///< camera stream to replay; "" = the session's only camera
  std::string stream{};        ///< stream name in the new session; "" = the recorded name
  int64_t origin_ns = 0;       ///< recording time (the session's host clock) played at start_host_ns
  int64_t start_host_ns = 0;   ///< CLOCK_MONOTONIC time of origin_ns; 0 = when streaming starts
  /// A frame handed to the sink later than this after it was due counts as late (device_status).
  double late_after_ms = 5.0;
  /// Records decoded ahead of their time (a 640x480 RGB-D frame takes about 2 MB here).
  int prefetch_frames = 90;
  void check() const;  ///< throws InputError
};

/// Record k is pushed at start_host_ns + (stamp_k - origin_ns) with the recording's frame number,
/// device ticks, colour and depth, stamped with the time it was due (a camera stamps the exposure, not
/// the moment software got to it). Images are decoded ahead (prefetch_frames). Records due before
/// streaming started are skipped (counted); a record handed over late keeps its due stamp and is
/// counted late (device_status: late_frames, max_late_ms). Throws InputError (a missing session or camera)
/// when created; a frame that cannot be read becomes an "error" event and is not pushed.
std::unique_ptr<CaptureSource> CreateSessionCameraReplay(const SessionCameraReplayOptions& options);
/// The same over a session already open (`session` is options.session_dir's), so a caller that read it
/// does not read it again.
std::unique_ptr<CaptureSource> CreateSessionCameraReplay(const SessionCameraReplayOptions& options, SessionReader session);

/// The bodies of `tracker` in `session` ("" = its only tracker) as recorded, in the manifest's order.
/// Throws InputError when the tracker is absent or ambiguous.
std::vector<ndi::RecordedBody> RecordedBodies(const SessionReader& session, const std::string& tracker);

/// The name of a session's only camera / tracker ("" when it has none); InputError when several.
std::string OnlyCamera(const SessionManifest& manifest);
std::string OnlyTracker(const SessionManifest& manifest);

/// The earliest stamp of any camera frame or tracker sample of the session (ns), the natural origin.
int64_t FirstStampNs(const SessionReader& session);

}  // namespace mocap::capture
