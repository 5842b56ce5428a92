#pragma once
// The visibility tolerance of the measured-depth test (BOP's mask_visib rule, formats.md §1) made to
// grow with depth for Kinect noise (kinect.md §8):
//
//   delta(z) = delta_base_m + noise_sigmas * noise_coeff_per_m * z^2
//
// with z the rendered depth (metres). The defaults are BOP19's 15 mm plus 3 sigma of Kinect v1's axial
// noise sigma_Z = 1.425e-3 * Z^2 (Khoshelham & Elberink 2012): 19.3 mm at 1 m, 32.1 mm at 2 m, 53.5 mm
// at 3 m. noise_sigmas = 0 gives BOP's fixed delta exactly (for datasets compared against BOP's tools).
namespace mocap {

struct VisibilityOptions {
  double delta_base_m = 0.015;
  double noise_sigmas = 3.0;
  double noise_coeff_per_m = 1.425e-3;  ///< sigma_Z / Z^2, 1/m (Kinect v1); Kinect v2 is ~1e-3 at 1-2 m

  /// Tolerance in metres at rendered depth z_m.
  double delta_m(double z_m) const { return delta_base_m + noise_sigmas * noise_coeff_per_m * z_m * z_m; }
  /// Throws InputError when a value is negative or not finite.
  void check() const;
};

}  // namespace mocap
