#pragma once
// `mocaplabel calibrate depth-to-color S --board B`: a Kinect v2's depth-to-colour extrinsic from a
// session of the board (calibrate/depth_to_color.h): per frame the board's pose from the colour image
// and its plane fitted to the depth pixels that fall on it (found with the device's extrinsic, which is
// close enough to select them); the result goes into the rig's `T_color_depth`.
#include "calibrate/depth_to_color.h"
#include "cli/calibrate_views.h"

namespace mocap::cli {

int CalibrateDepthToColorOfSession(const BoardSessionArgs& args, const DepthToColorOptions& options);

}  // namespace mocap::cli
