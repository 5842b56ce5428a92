#pragma once
// The rig's device sources and the simulated sources, each behind CaptureSource (source.h) and made
// by a factory returning unique_ptr.
//
// Kinect1 (libfreenect, capture/kinect): one record per colour + depth pair, stamped with the depth
// image's host receive time; `frame` counts the pairs this source delivered (so a frame dropped later in
// the pipeline shows as a skipped number). When the stream ends by itself (unplugged, USB error) the
// source logs an "error" event, reopens the device with exponential backoff, logs "reconnect", and a
// "gap" event with the first frame after it. Under the fakenect replay the end of the recording is the
// end of the stream: a "warning" event, not reopened (fakenect 0.5.3 would not replay it again). A
// fakenect source starts with the daemon's first session (CaptureSource::starts_with_session).
//
// NDI (capture/ndi NdiClient): one record per body per tracker frame; client events become session
// events: kGap -> "gap", kDisconnected -> "error", kReconnected -> "reconnect", damaged replies and
// ERRORxx answers -> "error", system status changes -> "note"; every body without a pose for
// no_pose_warning_s -> "warning" (once, until a pose comes back: "note").
#include <memory>
#include <optional>
#include <string>
#include <variant>

#include "capture/daemon/source.h"
#include "capture/kinect/kinect1_device.h"
#include "capture/kinect/kinect2_support.h"
#include "capture/ndi/client.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap::capture {

struct Kinect1SourceOptions {
  std::string stream = "kinect1";  ///< camera stream name in the session
  Kinect1Options device;
  std::optional<PinholeCamera> color_camera;  ///< calibrated colour intrinsics (else the depth image's)
  std::string camera_body;                    ///< tracker body carrying the camera ("" if none)
  Rigid3d T_body_camera;                      ///< mount: colour optical frame into the body frame
  bool reconnect = true;                      ///< reopen the device when its stream ends (not for replays)
  int reconnect_initial_ms = 200;             ///< backoff doubles from this ...
  int reconnect_max_ms = 5000;                ///< ... up to this
  void check() const;
};
std::unique_ptr<CaptureSource> CreateKinect1Source(const Kinect1SourceOptions& options);

/// Kinect2 (libfreenect2, capture/kinect/kinect2_support.h; a DeviceError at Open where this build has
/// no libfreenect2): one record per colour + depth pair as libfreenect2's SyncMultiFrameListener hands
/// them over, stamped with the colour image's receive time and ticks (the labelled image). Colour that
/// arrives as JPEG is recorded as it came; colour that libfreenect2 decoded (its stock pipelines) is
/// encoded to JPEG here, on the device thread (a 1080p PNG per frame would not keep up with 30 Hz).
/// When the stream ends (unplugged) an "error" event says so; the device is not reopened.
struct Kinect2SourceOptions {
  std::string stream = "kinect2";  ///< camera stream name in the session
  Kinect2Options device;
  std::optional<PinholeCamera> color_camera;  ///< calibrated colour intrinsics (else the device's)
  std::string camera_body;                    ///< tracker body carrying the camera ("" if none)
  Rigid3d T_body_camera;                      ///< mount: colour optical frame into the body frame
  int jpeg_quality = 95;                      ///< for colour that libfreenect2 hands over decoded
  void check() const;
};
std::unique_ptr<CaptureSource> CreateKinect2Source(const Kinect2SourceOptions& options);

/// A Kinect's manifest entry: its images as the device gives them (depth in mm) and the rig's mount.
struct KinectStream {
  std::string name, model, serial;
  PinholeCamera color_camera, depth_camera;
  bool registered = false;
  std::string camera_body;
  Rigid3d T_body_camera;
};
CameraStreamInfo KinectStreamInfo(const KinectStream& kinect);

/// A camera of the rig's `capture:` section.
using CameraSourceOptions = std::variant<Kinect1SourceOptions, Kinect2SourceOptions>;
const std::string& StreamOf(const CameraSourceOptions& camera);
std::unique_ptr<CaptureSource> CreateCameraSource(const CameraSourceOptions& camera);
/// Puts the rig's calibration of the camera (cameras[] of the same name) into its options.
void SetCalibration(CameraSourceOptions& camera, const std::optional<PinholeCamera>& color_camera,
                    const std::string& camera_body, const Rigid3d& T_body_camera);

struct NdiSourceOptions {
  std::string stream = "ndi";     ///< tracker stream name in the session
  std::string model = "polaris";  ///< manifest model
  ndi::NdiClientOptions client;
  /// The tracker replays a recording (`mocaplabel ndi-emulator --replay`, whose replay starts at
  /// TSTART): tracking starts with the daemon's first session, with a replayed camera.
  bool replay = false;
  /// Every body without a pose this long raises one "warning" event (tools hidden, or a replay that
  /// ended); a pose again raises a "note".
  double no_pose_warning_s = 2.0;
  void check() const;
};
std::unique_ptr<CaptureSource> CreateNdiSource(const NdiSourceOptions& options);

/// Simulated sources for benchmarks and tests of the pipeline: a moving test pattern (RGB + depth) and
/// bodies on circles. rate_hz = 0 means unthrottled: as fast as the sink takes them, where a sink that
/// reports back-pressure (`ready`) is waited for instead of overrun.
struct SimulatedCameraOptions {
  std::string stream = "simcam";
  std::string model = "sim";      ///< the manifest's model (SimulatedKinect1/2 set "kinect1"/"kinect2")
  int width = 640, height = 480;  ///< colour
  int depth_width = 0, depth_height = 0;  ///< 0: the colour's size, registered to it (as a Kinect1's)
  /// Colour handed over as JPEG bytes, as a Kinect v2 sends it (each pattern is encoded once, at
  /// construction), so the recording path stores it without encoding; else BGR pixels.
  bool color_jpeg = false;
  int jpeg_quality = 90;              ///< of those JPEGs
  double ticks_per_second = 60e6;     ///< device clock: Kinect1 60 MHz, Kinect2 8000 (0.125 ms)
  double rate_hz = 30;
  int64_t max_frames = 0;  ///< 0: until stopped
  void check() const;
};
/// A Kinect v1 (640x480 RGB and registered depth, 60 MHz ticks) and a Kinect v2 at its full sizes
/// (1920x1080 JPEG colour and 512x424 depth in one record, 0.125 ms ticks), both at 30 Hz.
SimulatedCameraOptions SimulatedKinect1(const std::string& stream);
SimulatedCameraOptions SimulatedKinect2(const std::string& stream);
struct SimulatedTrackerOptions {
  std::string stream = "simtracker";
  int bodies = 2;
  double rate_hz = 400;
  int64_t max_frames = 0;  ///< tracker frames (each gives `bodies` samples); 0: until stopped
  void check() const;
};
/// Back-pressure for unthrottled simulated sources: true when the sink can take another item now.
using ReadyFn = std::function<bool()>;
std::unique_ptr<CaptureSource> CreateSimulatedCamera(const SimulatedCameraOptions& options, ReadyFn ready = {});
std::unique_ptr<CaptureSource> CreateSimulatedTracker(const SimulatedTrackerOptions& options, ReadyFn ready = {});

}  // namespace mocap::capture
