#include "sim/kinect1_model.h"

#include <algorithm>
#include <cmath>

#include "core/check.h"
#include "sim/rng.h"

namespace mocap::sim {

void Kinect1Options::check() const {
  if (!(noise_coefficient_per_m >= 0 && noise_coefficient_per_m < 0.1))
    throw InputError("kinect1.noise_coefficient_per_m", "must be in [0, 0.1)");
  if (!(disparity_a < 0 && disparity_b > 0)) throw InputError("kinect1.disparity_a/b", "need a < 0 < b");
  if (!(min_depth_m > 0 && max_depth_m > min_depth_m)) throw InputError("kinect1.min_depth_m/max_depth_m", "need 0 < min < max");
  const double d_near = Kinect1DisparityFromDepth(min_depth_m, *this), d_far = Kinect1DisparityFromDepth(max_depth_m, *this);
  // libfreenect reports at most FREENECT_DEPTH_MM_MAX_VALUE = 10 m.
  if (!(d_near >= 0 && d_far > d_near && d_far < kKinect1NoDisparity - 1 && max_depth_m <= 10.0))
    throw InputError("kinect1.min_depth_m/max_depth_m", "range exceeds what 11-bit disparities can represent");
  if (quantise && noise_coefficient_per_m / -disparity_a < std::sqrt(1.0 / 12.0))
    throw InputError("kinect1.noise_coefficient_per_m", "smaller than the quantisation error alone");
  if (!(edge_jump_fraction > 0 && edge_min_jump_m >= 0)) throw InputError("kinect1.edge_jump_fraction", "must be positive");
  if (!(edge_invalid_probability >= 0 && edge_invalid_probability <= 1))
    throw InputError("kinect1.edge_invalid_probability", "must be in [0, 1]");
  if (!(color_noise_sigma >= 0 && color_noise_sigma < 64)) throw InputError("kinect1.color_noise_sigma", "must be in [0, 64)");
}

double Kinect1DepthSigmaM(double z_m, const Kinect1Options& options) { return options.noise_coefficient_per_m * z_m * z_m; }

double Kinect1DisparityFromDepth(double z_m, const Kinect1Options& options) {
  return (1.0 / z_m - options.disparity_b) / options.disparity_a;
}

double Kinect1DepthFromDisparity(double disparity, const Kinect1Options& options) {
  return 1.0 / (options.disparity_a * disparity + options.disparity_b);
}

PinholeCamera Kinect1ColorCamera() {
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = camera.fy = 525.0;
  camera.cx = 319.5;
  camera.cy = 239.5;
  return camera;
}

namespace {

ColorImage AddColorNoise(const ColorImage& clean, double sigma, uint64_t seed) {
  ColorImage noisy = clean;
  if (sigma <= 0) return noisy;
  // One random stream per row: the result does not depend on the number of threads.
#pragma omp parallel for schedule(static)
  for (int v = 0; v < noisy.height; ++v) {
    Rng rng = Rng::Derive(seed, 0x10000u + static_cast<uint64_t>(v));
    for (int u = 0; u < noisy.width; ++u)
      for (uint8_t& channel : noisy.at(u, v))
        channel = static_cast<uint8_t>(std::clamp(std::lround(channel + rng.Normal(sigma)), 0L, 255L));
  }
  return noisy;
}

}  // namespace

Kinect1Frame SimulateKinect1(const DepthImage& clean_depth_m, const ColorImage& clean_color, const PinholeCamera& camera,
                             const Kinect1Options& options, uint64_t seed, const DepthLoss& loss,
                             const LabelImage* instances) {
  MOCAP_CHECK(clean_depth_m.width == camera.width && clean_depth_m.height == camera.height, "depth and camera sizes differ");
  MOCAP_CHECK(clean_color.empty() || (clean_color.width == camera.width && clean_color.height == camera.height),
              "colour and camera sizes differ");
  MOCAP_CHECK(loss.empty() || (instances && instances->width == camera.width && instances->height == camera.height),
              "depth loss needs the instance ids of the camera's size");
  Kinect1Frame frame;
  frame.depth_m = DepthImage(camera.width, camera.height, 0.0f);
  frame.raw_disparity = Image<uint16_t>(camera.width, camera.height, kKinect1NoDisparity);
  const MaskImage projector_shadow = ShadowMask(clean_depth_m, camera, options.projector_x_m);
  const MaskImage ir_hidden = ShadowMask(clean_depth_m, camera, options.ir_camera_x_m);
  const MaskImage edges = DepthEdgeMask(clean_depth_m, options.edge_jump_fraction, options.edge_min_jump_m);
  const double sigma_d_total = options.noise_coefficient_per_m / -options.disparity_a;
  const double sigma_d = options.quantise ? std::sqrt(sigma_d_total * sigma_d_total - 1.0 / 12.0) : sigma_d_total;
  int shadow = 0, edge = 0, out_of_range = 0, lost = 0;
#pragma omp parallel for schedule(static) reduction(+ : shadow, edge, out_of_range, lost)
  for (int v = 0; v < camera.height; ++v) {
    // One random stream per row, drawn for every pixel: reproducible whatever the scene and threads.
    Rng rng = Rng::Derive(seed, static_cast<uint64_t>(v));
    for (int u = 0; u < camera.width; ++u) {
      const double noise = rng.Normal(sigma_d);
      const bool drop_edge = rng.Bernoulli(options.edge_invalid_probability);
      const float z = clean_depth_m.at(u, v);
      if (!(z > 0)) continue;
      if (projector_shadow.at(u, v) || ir_hidden.at(u, v)) {
        ++shadow;
        continue;
      }
      if (edges.at(u, v) && drop_edge) {
        ++edge;
        continue;
      }
      if (!loss.empty() && loss.Lost(u, v, instances->at(u, v), seed)) {
        ++lost;
        continue;
      }
      double d = Kinect1DisparityFromDepth(z, options) + noise;
      if (options.quantise) d = std::round(d);
      const double measured = Kinect1DepthFromDisparity(d, options);
      if (d < 0 || d >= kKinect1NoDisparity || measured < options.min_depth_m || measured > options.max_depth_m) {
        ++out_of_range;
        continue;
      }
      frame.depth_m.at(u, v) = static_cast<float>(measured);
      frame.raw_disparity.at(u, v) = static_cast<uint16_t>(std::clamp(std::lround(d), 0L, 2046L));
    }
  }
  frame.shadow_pixels = shadow;
  frame.edge_pixels = edge;
  frame.out_of_range_pixels = out_of_range;
  frame.lost_pixels = lost;
  frame.color = AddColorNoise(clean_color, options.color_noise_sigma, seed);
  return frame;
}

}  // namespace mocap::sim
