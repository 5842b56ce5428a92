#include "sim/kinect2_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/check.h"
#include "sim/depth_geometry.h"
#include "sim/rng.h"

namespace mocap::sim {

void Kinect2Options::check() const {
  if (!(min_depth_m > 0 && max_depth_m > min_depth_m)) throw InputError("kinect2.min_depth_m/max_depth_m", "need 0 < min < max");
  if (!(max_incidence_deg > 0 && max_incidence_deg < 90)) throw InputError("kinect2.max_incidence_deg", "must be in (0, 90)");
  if (!(edge_jump_m > 0)) throw InputError("kinect2.edge_jump_m", "must be positive");
  if (!(flying_pixel_probability >= 0 && flying_pixel_probability <= 1))
    throw InputError("kinect2.flying_pixel_probability", "must be in [0, 1]");
  if (!(std::abs(colour_delay_ms) < 100 && colour_jitter_ms >= 0 && colour_jitter_ms < 50))
    throw InputError("kinect2.colour_delay_ms/colour_jitter_ms", "delay must be within +-100 ms, jitter in [0, 50)");
  if (!(color_noise_sigma >= 0 && color_noise_sigma < 64)) throw InputError("kinect2.color_noise_sigma", "must be in [0, 64)");
}

double Kinect2DepthSigmaM(double z_m, double incidence_rad) {
  const double theta = std::min(incidence_rad, RadFromDeg(85.0));
  const double grazing = theta * theta / std::pow(std::numbers::pi / 2 - theta, 2);
  return 1e-3 * (1.5 - 0.5 * z_m + 0.3 * z_m * z_m + 0.1 * std::pow(z_m, 1.5) * grazing);
}

namespace {

/// Nearest and farthest valid depth in the 3x3 neighbourhood.
std::pair<float, float> NeighbourhoodRange(const DepthImage& depth_m, int u, int v) {
  float lo = depth_m.at(u, v), hi = lo;
  for (int dv = -1; dv <= 1; ++dv)
    for (int du = -1; du <= 1; ++du) {
      if (!depth_m.contains(u + du, v + dv)) continue;
      const float z = depth_m.at(u + du, v + dv);
      if (!(z > 0)) continue;
      lo = std::min(lo, z);
      hi = std::max(hi, z);
    }
  return {lo, hi};
}

const ReflectiveSurface* FindSurface(std::span<const ReflectiveSurface> reflective, uint16_t id) {
  for (const ReflectiveSurface& s : reflective)
    if (s.instance_id == id && id != 0 && s.reflectivity > 0) return &s;
  return nullptr;
}

}  // namespace

Kinect2DepthFrame SimulateKinect2Depth(const DepthImage& clean_depth_m, const LabelImage& instances,
                                       const PinholeCamera& depth_camera, std::span<const ReflectiveSurface> reflective,
                                       const Kinect2Options& options, uint64_t seed) {
  MOCAP_CHECK(clean_depth_m.width == depth_camera.width && clean_depth_m.height == depth_camera.height,
              "depth and camera sizes differ");
  MOCAP_CHECK(instances.empty() || (instances.width == clean_depth_m.width && instances.height == clean_depth_m.height),
              "instance and depth sizes differ");
  const Image<float> incidence = IncidenceAngleImage(clean_depth_m, depth_camera);
  const double max_incidence = RadFromDeg(options.max_incidence_deg);
  Kinect2DepthFrame frame;
  frame.depth_m = DepthImage(clean_depth_m.width, clean_depth_m.height, 0.0f);
  int flying = 0, deformed = 0, grazing = 0, out_of_range = 0;
#pragma omp parallel for schedule(static) reduction(+ : flying, deformed, grazing, out_of_range)
  for (int v = 0; v < clean_depth_m.height; ++v) {
    Rng rng = Rng::Derive(seed, 0x20000u + static_cast<uint64_t>(v));
    for (int u = 0; u < clean_depth_m.width; ++u) {
      const double noise = rng.Normal(), mix = rng.Uniform(0.1, 0.9);
      const bool fly = rng.Bernoulli(options.flying_pixel_probability);
      const float z_clean = clean_depth_m.at(u, v);
      if (!(z_clean > 0)) continue;
      const double theta = std::max(0.0f, incidence.at(u, v));
      if (theta > max_incidence) {
        ++grazing;
        continue;
      }
      double z = z_clean;
      const ReflectiveSurface* surface = instances.empty() ? nullptr : FindSurface(reflective, instances.at(u, v));
      if (surface != nullptr) {
        // Displacement along the ray (range r = z * |(x, y, 1)|), converted back to depth.
        const double range_per_depth = depth_camera.Ray({u, v}).norm();
        z += surface->reflectivity * surface->tof_deformation_m * (1.0 - std::cos(theta)) / range_per_depth;
        ++deformed;
      }
      const auto [near, far] = NeighbourhoodRange(clean_depth_m, u, v);
      if (far - near > options.edge_jump_m && fly) {
        z = mix * near + (1.0 - mix) * far;
        ++flying;
      }
      if (options.tof_noise) z += noise * Kinect2DepthSigmaM(z, theta);
      if (z < options.min_depth_m || z > options.max_depth_m) {
        ++out_of_range;
        continue;
      }
      frame.depth_m.at(u, v) = static_cast<float>(z);
    }
  }
  frame.flying_pixels = flying;
  frame.deformed_pixels = deformed;
  frame.grazing_pixels = grazing;
  frame.out_of_range_pixels = out_of_range;
  return frame;
}

ColorImage SimulateKinect2Color(const ColorImage& clean_color, const Kinect2Options& options, uint64_t seed) {
  ColorImage noisy = clean_color;
  if (options.color_noise_sigma <= 0) return noisy;
#pragma omp parallel for schedule(static)
  for (int v = 0; v < noisy.height; ++v) {
    Rng rng = Rng::Derive(seed, 0x30000u + static_cast<uint64_t>(v));
    for (int u = 0; u < noisy.width; ++u)
      for (uint8_t& channel : noisy.at(u, v))
        channel = static_cast<uint8_t>(std::clamp(std::lround(channel + rng.Normal(options.color_noise_sigma)), 0L, 255L));
  }
  return noisy;
}

int64_t Kinect2ColorTimeNs(int64_t depth_time_ns, int frame_index, const Kinect2Options& options, uint64_t seed) {
  Rng rng = Rng::Derive(seed ^ 0x6b32ULL, static_cast<uint64_t>(frame_index));
  const double delay_ms = options.colour_delay_ms + rng.Normal(options.colour_jitter_ms);
  return depth_time_ns + std::llround(delay_ms * 1e6);
}

PinholeCamera Kinect2DepthCamera() {
  PinholeCamera camera;
  camera.width = 512;
  camera.height = 424;
  camera.fx = camera.fy = 365.5;
  camera.cx = 255.5;
  camera.cy = 211.5;
  return camera;
}

PinholeCamera Kinect2ColorCamera() {
  PinholeCamera camera;
  camera.width = 1920;
  camera.height = 1080;
  camera.fx = camera.fy = 1060.0;
  camera.cx = 959.5;
  camera.cy = 539.5;
  return camera;
}

Rigid3d Kinect2TColorDepth() { return Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.052, 0.0, 0.0)); }

}  // namespace mocap::sim
