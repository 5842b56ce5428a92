#pragma once
// Kinect v1 (structured light) on a clean rendered frame: 640x480 colour and depth registered to it.
// Artefacts (kinect.md §8):
//  - random depth error sigma_z = k z^2 with k = 1.425e-3 m^-1 (Khoshelham & Elberink, Sensors 2012:
//    sigma_Z = (m / (f b)) Z^2 sigma_d, m/(f b) ~ 2.85e-3, sigma_d ~ 1/2 disparity unit);
//  - disparity quantisation: depth goes through the 11-bit raw disparity d with
//    z = 1 / (a d + b), a = -0.0030711, b = 3.3309495 (N. Burrus, libfreenect glpclview.c), so the
//    depth step is |a| z^2 (3.1 mm at 1 m). The Gaussian disparity noise is chosen so that, together
//    with the quantisation (variance 1/12 step^2), the total error is k z^2: sigma_pre^2 + 1/12 =
//    (k / |a|)^2 in disparity units;
//  - no depth where the projector's pattern cannot reach (its shadow) or the IR camera cannot see:
//    both found by an occlusion test on the depth map (ShadowMask);
//  - pixels at depth discontinuities dropped (the correlation window straddles two surfaces);
//  - out-of-range depths dropped; optional Gaussian colour noise;
//  - optionally, dark or shiny surfaces without depth in patches (sim/depth_loss.h).
#include <cstdint>

#include "core/camera.h"
#include "core/image.h"
#include "sim/color_image.h"
#include "sim/depth_geometry.h"
#include "sim/depth_loss.h"

namespace mocap::sim {

struct Kinect1Options {
  double noise_coefficient_per_m = 1.425e-3;  ///< k in sigma_z = k z^2
  bool quantise = true;                       ///< pass depth through the 11-bit disparity
  double disparity_a = -0.0030711;            ///< z = 1 / (a d + b)
  double disparity_b = 3.3309495;
  double min_depth_m = 0.5;
  double max_depth_m = 5.0;
  /// Registered depth is given in the colour camera frame; the IR camera and the projector sit on its x
  /// axis (Kinect v1 seen from behind: IR camera 2.5 cm to the left of the RGB camera, projector 7.5 cm
  /// to the right of the IR camera).
  double ir_camera_x_m = -0.025;
  double projector_x_m = 0.050;
  double edge_jump_fraction = 0.03;  ///< discontinuity: neighbour depth differs by 3 % of the depth ...
  double edge_min_jump_m = 0.01;     ///< ... and by at least 1 cm
  double edge_invalid_probability = 0.8;
  double color_noise_sigma = 2.0;    ///< 8-bit levels, per channel; 0 disables
  /// Throws InputError naming the field.
  void check() const;
};

/// Raw 11-bit disparity value meaning "no depth" (libfreenect FREENECT_DEPTH_11BIT).
constexpr uint16_t kKinect1NoDisparity = 2047;

struct Kinect1Frame {
  DepthImage depth_m;                ///< registered to the colour image; 0 = no depth
  Image<uint16_t> raw_disparity;     ///< the 11-bit values behind depth_m (2047 = none)
  ColorImage color;
  int shadow_pixels = 0;             ///< dropped: projector shadow or hidden from the IR camera
  int edge_pixels = 0;               ///< dropped at discontinuities
  int out_of_range_pixels = 0;
  int lost_pixels = 0;               ///< dropped on dark or shiny surfaces (DepthLoss)
};

/// sigma_z (metres) of the model at depth z.
double Kinect1DepthSigmaM(double z_m, const Kinect1Options& options = {});
/// Continuous raw disparity at depth z, and depth of a (possibly fractional) raw disparity.
double Kinect1DisparityFromDepth(double z_m, const Kinect1Options& options = {});
double Kinect1DepthFromDisparity(double disparity, const Kinect1Options& options = {});

/// Applies the Kinect v1 model to a clean rendered frame (depth in metres, 0 = nothing; colour may be
/// empty). `seed` makes the noise reproducible (derive one per frame). Precondition: depth has the
/// camera's size; colour is empty or the same size. With `loss` (not empty), `instances` (the clean
/// render's instance ids, the camera's size) tells which surface each pixel shows.
Kinect1Frame SimulateKinect1(const DepthImage& clean_depth_m, const ColorImage& clean_color, const PinholeCamera& camera,
                             const Kinect1Options& options, uint64_t seed, const DepthLoss& loss = {},
                             const LabelImage* instances = nullptr);

/// The registered colour camera of a Kinect v1 at 640x480 (commonly used calibration, fx = fy = 525).
PinholeCamera Kinect1ColorCamera();

}  // namespace mocap::sim
