#pragma once
// Kinect v2 (time of flight) on clean rendered frames: 512x424 depth from the IR camera and 1920x1080
// colour from the colour camera, taken at different instants. Artefacts (kinect.md §6, §8):
//  - axial noise sigma_z[mm] = 1.5 - 0.5 z + 0.3 z^2 + 0.1 z^1.5 theta^2 / (pi/2 - theta)^2 (z in m,
//    theta the incidence angle; Fankhauser et al., ICAR 2015);
//  - flying pixels at depth edges: the pixel integrates both surfaces and reports a depth between them;
//  - deformation of reflective surfaces (the paper's oil-bottle failure, SegICP §V): multipath adds path
//    length, modelled as a displacement along the ray of reflectivity * tof_deformation_m *
//    (1 - cos theta), growing from 0 where the surface faces the camera to the full amount at grazing
//    incidence; a phenomenological model, not a fitted one;
//  - colour and depth are not synchronised (libfreenect2 #721; colour lags depth, iai_kinect2 #452): the
//    colour frame is taken colour_delay_ms (+ jitter) after the depth frame;
//  - no depth beyond 0.5-4.5 m (libfreenect2 Config) or at grazing incidence.
#include <cstdint>
#include <span>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "sim/color_image.h"

namespace mocap::sim {

struct Kinect2Options {
  double min_depth_m = 0.5;
  double max_depth_m = 4.5;
  bool tof_noise = true;
  double max_incidence_deg = 80.0;        ///< no return beyond this incidence angle
  double edge_jump_m = 0.04;              ///< a 3x3 depth spread larger than this makes an edge pixel
  double flying_pixel_probability = 0.6;  ///< chance that an edge pixel reports a mixed depth
  double colour_delay_ms = 15.0;          ///< colour exposure after the depth exposure
  double colour_jitter_ms = 4.0;          ///< RMS variation of that delay
  double color_noise_sigma = 2.0;         ///< 8-bit levels, per channel; 0 disables
  /// Throws InputError naming the field.
  void check() const;
};

/// A surface that deforms ToF depth: pixels of `instance_id` in the instance image.
struct ReflectiveSurface {
  uint16_t instance_id = 0;
  double reflectivity = 0;       ///< 0..1
  double tof_deformation_m = 0;  ///< displacement at grazing incidence for reflectivity 1
};

struct Kinect2DepthFrame {
  DepthImage depth_m;       ///< 0 = no depth
  int flying_pixels = 0;
  int deformed_pixels = 0;  ///< pixels on reflective surfaces that were displaced
  int grazing_pixels = 0;   ///< dropped at grazing incidence
  int out_of_range_pixels = 0;
};

/// sigma_z (metres) of the Fankhauser model at depth z and incidence theta (radians, < pi/2).
double Kinect2DepthSigmaM(double z_m, double incidence_rad);

/// Applies the ToF model to a clean depth frame rendered from the IR camera, with the instance ids of
/// the same render. Precondition: depth and instances have the camera's size (instances may be empty
/// when no surface is reflective).
Kinect2DepthFrame SimulateKinect2Depth(const DepthImage& clean_depth_m, const LabelImage& instances,
                                       const PinholeCamera& depth_camera, std::span<const ReflectiveSurface> reflective,
                                       const Kinect2Options& options, uint64_t seed);

/// Colour noise on the 1920x1080 render.
ColorImage SimulateKinect2Color(const ColorImage& clean_color, const Kinect2Options& options, uint64_t seed);

/// Exposure time of the colour frame that goes with the depth frame exposed at `depth_time_ns`.
int64_t Kinect2ColorTimeNs(int64_t depth_time_ns, int frame_index, const Kinect2Options& options, uint64_t seed);

/// Typical factory intrinsics of a Kinect v2 (iai_kinect2 calibrations of several units) and the
/// colour-from-depth offset (the colour camera 5.2 cm along the IR camera's +x).
PinholeCamera Kinect2DepthCamera();
PinholeCamera Kinect2ColorCamera();
Rigid3d Kinect2TColorDepth();

}  // namespace mocap::sim
