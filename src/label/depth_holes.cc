#include "label/depth_holes.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mocap {
namespace {

/// Rows, columns and diagonals, as (du, dv).
constexpr int kDirections[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};

}  // namespace

double RayLength(const PinholeCamera& camera, int u, int v) {
  if (!camera.has_distortion()) {
    const double x = (u - camera.cx) / camera.fx, y = (v - camera.cy) / camera.fy;
    return std::sqrt(x * x + y * y + 1.0);
  }
  return camera.Ray({u, v}).norm();
}

HoleJudge::HoleJudge(const RenderOutput& render, const PinholeCamera& camera, const DepthImage& measured_depth_m,
                     const VisibilityOptions& options)
    : render_(render), camera_(camera), measured_(measured_depth_m), options_(options) {}

HoleJudge::Sample HoleJudge::Classify(const ObjectLayer& layer, int x, int y, float z_m) const {
  const float measured = measured_.at(x, y);
  if (!(measured > 0.0f)) return Sample::kNone;
  const uint16_t nearest = render_.instance_ids.at(x, y);
  if (nearest != 0 && nearest != layer.instance_id) {
    const double z_model = render_.depth_m.at(x, y);
    if (std::abs(z_model - measured) <= options_.delta_m(z_model)) return Sample::kSurface;  // explained
  }
  const float own = layer.depth_at(x, y);
  const double z_ref = own > 0.0f ? own : z_m;
  const double nearer_m = (z_ref - measured) * RayLength(camera_, x, y);
  return nearer_m > options_.delta_m(z_ref) ? Sample::kOccluder : Sample::kSurface;
}

void HoleJudge::FindReach() const {
  const int w = measured_.width, h = measured_.height;
  const auto limit = static_cast<uint16_t>(options_.hole_search_px);
  reach_.assign(8, Image<uint16_t>(w, h, 0));
  for (int k = 0; k < 8; ++k) {
    const auto [du, dv] = kDirections[k];
    Image<uint16_t>& reach = reach_[static_cast<size_t>(k)];
    // Visit (u + du, v + dv) before (u, v): rows against dv, and within a row against du.
    for (int i = 0; i < h; ++i) {
      const int v = dv > 0 ? h - 1 - i : i;
      for (int j = 0; j < w; ++j) {
        const int u = du > 0 ? w - 1 - j : j;
        const int x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= w || y >= h) continue;  // the image border: nothing beyond
        if (measured_.at(x, y) > 0.0f) {
          reach.at(u, v) = 1;
        } else {
          const uint16_t next = reach.at(x, y);
          reach.at(u, v) = next > 0 && next < limit ? static_cast<uint16_t>(next + 1) : 0;
        }
      }
    }
  }
}

bool HoleJudge::Occluded(const ObjectLayer& layer, int u, int v, float z_m) const {
  if (reach_.empty()) FindReach();
  constexpr double kNone = std::numeric_limits<double>::infinity();
  double occluder_px = kNone, surface_px = kNone;
  float occluder_z_m = 0;
  for (int k = 0; k < 8; ++k) {
    const int steps = reach_[static_cast<size_t>(k)].at(u, v);
    if (steps == 0) continue;
    const auto [du, dv] = kDirections[k];
    const int x = u + du * steps, y = v + dv * steps;
    const Sample sample = Classify(layer, x, y, z_m);
    const double distance_px = steps * (du != 0 && dv != 0 ? std::sqrt(2.0) : 1.0);
    if (sample == Sample::kSurface) {
      surface_px = std::min(surface_px, distance_px);
    } else if (distance_px < occluder_px) {
      occluder_px = distance_px, occluder_z_m = measured_.at(x, y);
    }
  }
  if (occluder_px == kNone) return false;  // no depth within reach, or only the object and what lies behind
  if (surface_px == kNone) return true;    // enclosed by nearer surfaces
  if (occluder_px <= options_.hole_edge_px) return true;
  const double shadow_px =
      std::max(0.0, camera_.fx * options_.hole_shadow_baseline_m * (1.0 / occluder_z_m - 1.0 / z_m));
  return surface_px > shadow_px + options_.hole_edge_px;
}

}  // namespace mocap
