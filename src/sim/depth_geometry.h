#pragma once
// Geometry on clean rendered depth maps shared by the sensor models: shadows cast by an emitter (or
// occlusion from a second viewpoint), depth discontinuities, and the incidence angle of each pixel.
#include <cstdint>

#include "core/camera.h"
#include "core/image.h"

namespace mocap::sim {

using MaskImage = Image<uint8_t>;  ///< 1 = set, 0 = not set

/// Pixels of `depth_m` whose surface point cannot be seen from a viewpoint at (baseline_x_m, 0, 0) in
/// the camera frame (a structured-light projector, or a second camera): a real occlusion test on the
/// depth map. Both viewpoints lie on the camera's x axis, so each image row is an epipolar line and the
/// test is a scan along the row: a point is hidden when a point nearer the viewpoint's side projects,
/// seen from the viewpoint, beyond it (the order along the row reverses), with a tolerance of
/// `tolerance_px` pixels. Exact for an undistorted camera; with distortion rows are only approximately
/// epipolar. Invalid (0) pixels neither cast nor receive shadows.
MaskImage ShadowMask(const DepthImage& depth_m, const PinholeCamera& camera, double baseline_x_m,
                     double tolerance_px = 0.3);

/// Pixels next to a depth discontinuity: an 8-neighbour is invalid, or differs by more than
/// `jump_fraction * depth` and `min_jump_m`. `band_px` >= 1 widens the band (Chebyshev distance).
MaskImage DepthEdgeMask(const DepthImage& depth_m, double jump_fraction, double min_jump_m, int band_px = 1);

/// Angle between each pixel's surface normal (from neighbouring depths on the same surface) and the line
/// of sight, radians in [0, pi/2]; -1 where there is no valid depth or no usable neighbour.
Image<float> IncidenceAngleImage(const DepthImage& depth_m, const PinholeCamera& camera, double max_step_fraction = 0.03);

}  // namespace mocap::sim
