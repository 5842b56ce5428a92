#pragma once
// The labeller's view of a rig (pipeline/rig.h derives it from rig.yaml; docs/rig.md). Every field is optional: what is not
// given comes from the session's manifest (the calibration it was recorded with), so re-labelling after
// a calibration fix is `mocaplabel label S --rig calib/new.yaml`.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap {

struct LabelRigCamera {
  std::string camera;                         ///< camera stream name in the session
  std::optional<PinholeCamera> color_camera;  ///< intrinsics of the colour stream
  std::optional<std::string> body;            ///< tracker body carrying the camera
  std::optional<Rigid3d> T_body_camera;       ///< camera mount: colour optical frame into the body frame
  std::optional<Rigid3d> T_color_depth;       ///< depth into colour optical frame (unregistered depth only)
};

struct LabelRig {
  std::string name;
  std::vector<LabelRigCamera> cameras;
  /// Tracker-to-camera latency: a camera frame stamped t shows the scene the tracker reports at
  /// t + tracker_latency_ns (positive when the tracker's stamps lag the camera's).
  int64_t tracker_latency_ns = 0;
  /// Throws InputError naming `where` on duplicate cameras or invalid intrinsics.
  void check(const std::string& where) const;
  const LabelRigCamera* Find(const std::string& camera) const;
};

}  // namespace mocap
