#pragma once
// The measured depth of a camera frame in its colour image, where the labels are: as stored when the
// sensor registers it (Kinect v1, TUM, BOP), else warped there through T_color_depth
// (core/depth_registration.h; Kinect v2), as the exporters do. The labeller, the scorer's visible masks
// (pipeline/scoring.h) and the validator (validate/session_check.cc) read depth through this, so they
// judge the same image. A registered image has holes the raw one has not: colour pixels the depth camera cannot see
// (the occlusion shadow of the baseline beside a nearer surface) and pixels no depth pixel reaches;
// the combined visibility rule judges them as any hole (label/depth_holes.h).
#include <optional>
#include <string>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "session/manifest.h"
#include "session/reader.h"

namespace mocap {

struct DepthInColor {
  bool registered = true;      ///< the stored depth is already in the colour image
  PinholeCamera depth_camera;  ///< intrinsics of the stored depth (unregistered only)
  PinholeCamera color_camera;  ///< the image the labels are in
  Rigid3d T_color_depth;       ///< depth optical frame into the colour optical frame

  /// `info`'s registration, with the labeller's colour intrinsics and, when the rig gives one, its
  /// T_color_depth (a calibration fix) in place of the manifest's.
  static DepthInColor Of(const CameraStreamInfo& info, const PinholeCamera& color_camera,
                         const std::optional<Rigid3d>& T_color_depth = std::nullopt);

  /// `depth_m` (as stored) in the colour image. Throws InputError when its size is not the stored
  /// depth's (the depth camera's, or the colour camera's when registered).
  DepthImage ToColor(DepthImage depth_m) const;
};

/// Loads frame `index` of `camera` and returns its depth in the colour image. Throws InputError as
/// SessionReader::LoadDepth does, or for a depth image of the wrong size.
DepthImage LoadDepthInColor(const SessionReader& session, const std::string& camera, int64_t index,
                            const DepthInColor& registration);

}  // namespace mocap
