#pragma once
// Which pixels of an object are visible, given the model z-buffer and the measured depth
// (docs/labels.md "Visible masks").
//
// Two rules:
//  - kBop19: BOP19's mask_visib exactly (bop_toolkit visibility.py): an amodal pixel is visible when the
//    measured depth is missing or rendered minus measured distance <= delta(z). It counts every pixel
//    without depth as visible, so an object behind an occluder that has no depth (nearer than the
//    sensor's minimum range, dark, shiny, at a depth edge) takes in the occluder's pixels.
//  - kCombined (the default): what is known, combined. A pixel hidden by a modelled object in the
//    z-buffer stays hidden whatever the depth says; where the model shows the object nearest, measured
//    depth decides as in BOP19 (it sees hands and other unmodelled occluders); a depth hole is judged
//    from the measured depth around it (HoleJudge, depth_holes.h): a hole enclosed by surfaces nearer
//    than the object is an occluder, a hole on the object's own surface or in a shadow cast onto it is
//    the object, and a hole with no measured depth within reach is left to the model. Then, given the
//    frame's colour image, a hole pixel left visible whose colour the object never shows is hidden
//    (hole_colour, hole_colour.h): a hand nearer than the sensor's range, which depth cannot see.
//
// The tolerance grows with depth for Kinect noise (kinect.md §8):
//
//   delta(z) = delta_base_m + noise_sigmas * noise_coeff_per_m * z^2
//
// with z the rendered depth (metres). The defaults are BOP19's 15 mm plus 3 sigma of Kinect v1's axial
// noise sigma_Z = 1.425e-3 * Z^2 (Khoshelham & Elberink 2012): 19.3 mm at 1 m, 32.1 mm at 2 m, 53.5 mm
// at 3 m. noise_sigmas = 0 gives BOP's fixed delta exactly (for datasets compared against BOP's tools).
#include <string>
#include <string_view>

namespace mocap {

enum class VisibilityRule { kCombined, kBop19 };

std::string_view ToString(VisibilityRule rule);
/// "combined" or "bop19"; throws InputError naming `where` otherwise.
VisibilityRule ParseVisibilityRule(std::string_view text, const std::string& where);

struct VisibilityOptions {
  VisibilityRule rule = VisibilityRule::kCombined;
  double delta_base_m = 0.015;
  double noise_sigmas = 3.0;
  double noise_coeff_per_m = 1.425e-3;  ///< sigma_Z / Z^2, 1/m (Kinect v1); Kinect v2 is ~1e-3 at 1-2 m

  // Depth holes (kCombined only).
  /// How far (pixels, along 8 directions) a hole pixel looks for measured depth around it. Beyond it the
  /// hole is judged by the model alone (a surface too near for the sensor, wholly without depth).
  int hole_search_px = 32;
  /// A hole pixel this close (pixels) to a nearer, unexplained surface is that surface's edge: depth
  /// sensors lose the pixels where their window straddles a discontinuity on both sides of it.
  int hole_edge_px = 1;
  /// The longest baseline between the colour camera and another viewpoint of the depth sensor (Kinect
  /// v1: the projector, 5 cm; the IR camera is 2.5 cm away). A nearer surface at z_near shadows up to
  /// fx * b * (1/z_near - 1/z) pixels of the object behind it, as the colour camera sees it; holes that
  /// wide beside an occluder are such shadows, on the object.
  double hole_shadow_baseline_m = 0.05;

  // Depth holes and colour (kCombined, and only when the frame's colour image is given; label/hole_colour.h).
  /// Hide hole pixels whose colour the object never shows, neither its pixels with depth nor its mesh
  /// (a hand nearer than the sensor's range). Needs the frame's colour image; it did no worse than
  /// without on any simulated scene (docs/labels.md), so it is on by default.
  bool hole_colour = true;
  int hole_colour_bins = 32;                 ///< chromaticity bins per axis (R and G over R + G + B)
  /// Mean 8-bit level below which a pixel has no usable colour: the chromaticity of a dark pixel is
  /// mostly the sensor's noise.
  int hole_colour_min_level = 45;
  int hole_colour_min_reference_px = 200;    ///< depth-confirmed pixels needed to know an object's colours
  double hole_colour_max_share = 0.002;      ///< a colour this rare among them (bin and neighbours) is foreign

  /// Tolerance in metres at rendered depth z_m.
  double delta_m(double z_m) const { return delta_base_m + noise_sigmas * noise_coeff_per_m * z_m * z_m; }
  /// Throws InputError when a value is negative, not finite or out of range.
  void check() const;
};

}  // namespace mocap
