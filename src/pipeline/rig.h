#pragma once
// The rig (rig.yaml, calib/*.yaml; schema in docs/rig.md and docs/capture.md): the one type holding a
// rig's calibration and its capture set-up. rig.yaml has one reader and one writer, both here; the
// labeller's view (LabelRig) and the capture daemon's options are derived from it.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "capture/daemon/control_server.h"
#include "capture/daemon/daemon.h"
#include "capture/daemon/sources.h"
#include "label/rig.h"

namespace mocap::pipeline {

/// A camera's calibration. Every field is optional: what is not given comes from the session.
struct RigCameraCalibration {
  std::string name;                           ///< camera stream name in the session
  std::optional<PinholeCamera> intrinsics;    ///< of the colour stream
  std::optional<std::string> body;            ///< tracker body carrying the camera
  std::optional<Rigid3d> T_body_camera;       ///< colour optical frame into the body frame
  /// Depth optical frame into the colour optical frame, for a sensor whose depth is not registered to
  /// its colour (Kinect v2): replaces the device's value the session recorded (calibrate depth-to-color).
  std::optional<Rigid3d> T_color_depth;
};

/// The `capture:` section: what the capture daemon connects to and where it writes.
struct RigCapture {
  std::string sessions_dir = "sessions";  ///< as written; relative to the rig file's folder
  capture::ControlServerOptions control;  ///< bind and port only
  int frame_queue = capture::RecorderOptions{}.frame_queue;
  int sample_queue = capture::RecorderOptions{}.sample_queue;
  std::optional<capture::NdiSourceOptions> tracker;
  /// `camera:` (one) or `cameras:` (a list), in the order given; calibration filled in by CaptureOptionsOf.
  std::vector<capture::CameraSourceOptions> cameras;
};

struct Rig {
  std::filesystem::path file;  ///< where it was read from ("" for one built in memory)
  std::string name;
  /// Tracker-to-camera latency: a camera frame stamped t shows the scene the tracker reports at
  /// t + tracker_latency_ns.
  int64_t tracker_latency_ns = 0;
  std::vector<RigCameraCalibration> cameras;
  std::optional<RigCapture> capture;
  const RigCameraCalibration* Find(const std::string& camera) const;
  /// Throws InputError naming `where` for a camera listed twice, bad intrinsics or empty names.
  void check(const std::string& where) const;
};

/// Reads a rig file: unknown keys (with "did you mean"), wrong types, a rotation that is not a rotation
/// and invalid values are InputErrors naming file:line and the key.
Rig ReadRig(const std::filesystem::path& path);
Rig ParseRig(const std::string& text, const std::string& file_name);

/// rig.yaml text (yaml-cpp's emitter, `comment` lines first) and its atomic write.
std::string EmitRig(const Rig& rig, const std::string& comment = "");
void WriteRig(const Rig& rig, const std::filesystem::path& path, const std::string& comment = "");

/// The labeller's view.
LabelRig LabelRigOf(const Rig& rig);

/// The capture daemon's options from the `capture:` section (sessions_dir resolved against the rig
/// file's folder, each camera's calibration from the rig). Throws InputError when there is none.
struct CaptureOptions {
  capture::CaptureDaemonOptions daemon;
  capture::ControlServerOptions control;
  std::optional<capture::NdiSourceOptions> tracker;
  std::vector<capture::CameraSourceOptions> cameras;
};
CaptureOptions CaptureOptionsOf(const Rig& rig);

}  // namespace mocap::pipeline
