#pragma once
// Depth registered to a colour camera: what a sensor whose depth camera sits beside its colour camera
// (Kinect v2: 512x424 time-of-flight beside 1920x1080 colour) does not deliver, and what the labels (in
// the colour image), the validator and the BOP/TUM exporters need.
#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"

namespace mocap {

/// Forward-warps every valid depth pixel into the colour image through T_color_depth. A depth pixel
/// covers about (f_colour / f_depth)^2 colour pixels at equal depth, so it is splatted over that
/// footprint with a z-test: the nearest surface wins, as a registered sensor would see it. Colour pixels
/// no depth pixel reaches stay 0 (no depth), never interpolated. Depth values are z in the colour frame.
DepthImage RegisterDepthToColor(const DepthImage& depth_m, const PinholeCamera& depth_camera,
                                const PinholeCamera& color_camera, const Rigid3d& T_color_depth);

}  // namespace mocap
