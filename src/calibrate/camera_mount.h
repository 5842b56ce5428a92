#pragma once
// Camera mount: where the camera's optical frame sits on its tracked body (T_cambody_camera), found
// together with where the board sits on the board's tracked body (T_boardbody_board), from views of
// the board by the camera while either one moves.
//
// Per view i the chain (DESIGN.md) closes through the image:
//   T_camera_board_i = inv(T_tracker_cambody_i * T_cambody_camera) * T_tracker_boardbody_i * T_boardbody_board
// Initialisation: T_camera_board_i by cv::solvePnP, then cv::calibrateRobotWorldHandEye (AX = ZB, see
// docs/calibration.md for the mapping of its frames onto ours). Refinement (Ceres): both transforms
// as 6-DoF (angle-axis, translation) minimising the board corners' reprojection error over all views
// under a robust (Huber) loss.
#include <span>
#include <string>
#include <vector>

#include "calibrate/board.h"
#include "calibrate/intrinsics.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap {

struct MountView {
  Rigid3d T_tracker_cambody;    ///< tracked camera body at the frame's time
  Rigid3d T_tracker_boardbody;  ///< tracked board body at the frame's time
  BoardDetection detection;     ///< the board in the frame
};

struct CameraMountOptions {
  int min_views = 8;                  ///< usable views needed
  int min_corners_per_view = 8;       ///< a view with fewer corners is rejected
  double max_pnp_rms_px = 2.0;        ///< a view whose own board pose fits worse is rejected
  double huber_px = 1.0;              ///< scale of the Huber loss on each corner's error
  double max_view_rms_px = 3.0;       ///< after refinement, views above are rejected and the fit redone once
  int max_iterations = 200;           ///< Ceres iterations
  double min_rotation_spread_deg = 10.0;  ///< largest relative rotation between views below this: a warning
  double min_axis_spread_deg = 10.0;      ///< relative rotation axes all within this of one axis: a warning
  /// Throws InputError naming the field.
  void check() const;
};

struct CameraMountResult {
  Rigid3d T_cambody_camera;
  Rigid3d T_boardbody_board;
  double initial_rms_px = 0;        ///< with the hand-eye initialisation
  double rms_px = 0;                ///< after refinement, all corners of the views used
  double rms_mm = 0;                ///< the same errors expressed on the board: px * depth / focal length
  std::vector<int> views_used;      ///< indices into the input views
  std::vector<double> view_rms_px;  ///< parallel to views_used
  std::vector<double> view_rms_mm;  ///< parallel to views_used
  std::vector<RejectedView> views_rejected;
  double rotation_spread_deg = 0;   ///< largest relative rotation between two views used
  double axis_spread_deg = 0;       ///< spread of the relative rotation axes about their main axis
  int iterations = 0;               ///< Ceres iterations of the last refinement
  std::vector<std::string> warnings;  ///< each says what to record instead
};

/// Solves for both mounts. The camera's intrinsics are held fixed. Throws InputError for invalid
/// options, spec or camera, a checkerboard spec (its half-turn ambiguity flips board poses), and
/// "too few usable views: N of M (need K); ..." with the reasons the others were rejected.
CameraMountResult CalibrateCameraMount(std::span<const MountView> views, const PinholeCamera& camera,
                                       const BoardSpec& spec, const CameraMountOptions& options = {});

/// The hand-eye initialisation alone: cv::calibrateRobotWorldHandEye (Shah) on per-view
/// T_camera_board (e.g. from solvePnP) and T_cambody_boardbody = inv(T_tracker_cambody) *
/// T_tracker_boardbody. Its cTw_i * wTb = cTg * gTb_i is our T_camera_board_i * T_board_boardbody =
/// T_camera_cambody * T_cambody_boardbody_i: world = board, base = board body, gripper = camera body.
/// Precondition: at least 3 views, the spans of equal size.
struct HandEyeMount {
  Rigid3d T_cambody_camera;
  Rigid3d T_boardbody_board;
};
HandEyeMount InitialiseMountHandEye(std::span<const Rigid3d> T_camera_board, std::span<const Rigid3d> T_cambody_boardbody);

/// The motion's richness for AX = ZB: the largest angle between the relative poses
/// T_cambody_boardbody of any two views (degrees), and the spread of the axes of those relative
/// rotations about their principal axis (degrees, atan of sqrt(second / first eigenvalue) of the
/// angle-weighted axis scatter); pairs rotating less than 2 degrees do not count towards the axes.
struct MotionSpread {
  double rotation_spread_deg = 0;
  double axis_spread_deg = 0;
};
MotionSpread MeasureMotionSpread(std::span<const Rigid3d> T_cambody_boardbody);

}  // namespace mocap
