#include "label/object_labels.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/check.h"

namespace mocap {
namespace {

/// Length of the ray (x, y, 1) through pixel (u, v): converts z along the optical axis to the distance
/// from the camera centre, which is what BOP's visibility test compares.
double RayLength(const PinholeCamera& camera, int u, int v) {
  if (!camera.has_distortion()) {
    const double x = (u - camera.cx) / camera.fx, y = (v - camera.cy) / camera.fy;
    return std::sqrt(x * x + y * y + 1.0);
  }
  return camera.Ray({u, v}).norm();
}

/// Longest pixel ray (x, y, 1) of the image: at a corner (distortion is monotonic in the radius).
double MaxRayLength(const PinholeCamera& camera) {
  double longest = 1.0;
  for (int u : {0, camera.width - 1})
    for (int v : {0, camera.height - 1}) longest = std::max(longest, RayLength(camera, u, v));
  return longest;
}

/// BOP19: visible when the measured depth is missing or the rendered distance exceeds the measured one
/// by at most delta (`bop_toolkit_lib/visibility.py`, mode bop19). The ray length (1 .. max_ray) is
/// only computed when the bounds do not decide.
bool VisibleInMeasured(const PinholeCamera& camera, int u, int v, float z_render, float z_measured,
                       double max_ray, const VisibilityOptions& options) {
  if (!(z_measured > 0.0f)) return true;
  const double dz = static_cast<double>(z_render) - z_measured;
  if (dz <= 0) return true;  // the surface is in front of (or at) what was measured: not occluded
  const double delta = options.delta_m(z_render);
  if (dz * max_ray <= delta) return true;
  if (dz > delta) return false;
  return dz * RayLength(camera, u, v) <= delta;
}

ObjectLabels LabelOne(const ObjectLayer& layer, const RenderOutput& render, const PinholeCamera& camera,
                      const DepthImage* measured, double max_ray, const VisibilityOptions& options) {
  ObjectLabels out;
  ObjectMasks& m = out.masks;
  ObjectStats& s = out.stats;
  m.instance_id = s.instance_id = layer.instance_id;
  m.rect = layer.rect;
  const size_t n = layer.depth_m.size();
  m.amodal.assign(n, 0);
  m.visible_model.assign(n, 0);
  if (measured) m.visible_measured.assign(n, 0);
  int valid = 0, visible_measured = 0, visible_model = 0, inside = 0;
  for (int v = m.rect.y; v < m.rect.y + m.rect.height; ++v) {
    // Row pointers, so that the pixel loop indexes without recomputing image offsets.
    const size_t row = static_cast<size_t>(v - m.rect.y) * m.rect.width;
    const float* z_row = layer.depth_m.data() + row;
    const uint16_t* id_row = &render.instance_ids.at(m.rect.x, v);
    const float* measured_row = measured ? &measured->at(m.rect.x, v) : nullptr;
    uint8_t* amodal = m.amodal.data() + row;
    uint8_t* model = m.visible_model.data() + row;
    uint8_t* consistent = measured ? m.visible_measured.data() + row : nullptr;
    for (int k = 0; k < m.rect.width; ++k) {
      const float z = z_row[k];
      if (!(z > 0.0f)) continue;
      amodal[k] = 1, ++inside;
      if (id_row[k] == layer.instance_id) model[k] = 1, ++visible_model;
      if (!measured_row) continue;
      const float zm = measured_row[k];
      valid += zm > 0.0f;
      if (VisibleInMeasured(camera, m.rect.x + k, v, z, zm, max_ray, options)) consistent[k] = 1, ++visible_measured;
    }
  }
  s.bbox_obj = layer.bbox_obj;
  s.px_count_all = layer.px_count_all;
  s.truncated_by_canvas = layer.truncated_by_canvas;
  s.outside_image = inside == 0;
  s.px_count_visib_model = visible_model;
  s.visib_fract_model = s.px_count_all > 0 ? static_cast<double>(visible_model) / s.px_count_all : 0.0;
  s.px_count_valid = measured ? valid : -1;
  s.px_count_visib = measured ? visible_measured : visible_model;
  s.visib_fract = s.px_count_all > 0 ? static_cast<double>(s.px_count_visib) / s.px_count_all : 0.0;
  s.bbox_visib = MaskBox(measured ? m.visible_measured : m.visible_model, m.rect);
  return out;
}

}  // namespace

void VisibilityOptions::check() const {
  for (double value : {delta_base_m, noise_sigmas, noise_coeff_per_m})
    if (!std::isfinite(value) || value < 0)
      throw InputError("visibility options", Str("delta_base_m, noise_sigmas and noise_coeff_per_m must be >= 0 (got ",
                                                 delta_base_m, ", ", noise_sigmas, ", ", noise_coeff_per_m, ")"));
}

PixelBox MaskBox(const std::vector<uint8_t>& mask, const PixelRect& rect) {
  int x0 = INT32_MAX, y0 = -1, x1 = -1, y1 = -1;
  const auto set = [](uint8_t m) { return m != 0; };
  for (int v = 0; v < rect.height; ++v) {
    // Each row only from both ends inwards to its first and last set pixel.
    const uint8_t* row = mask.data() + static_cast<size_t>(v) * rect.width;
    const uint8_t* first = std::find_if(row, row + rect.width, set);
    if (first == row + rect.width) continue;
    const auto last = std::find_if(std::make_reverse_iterator(row + rect.width), std::make_reverse_iterator(first), set);
    x0 = std::min(x0, static_cast<int>(first - row)), x1 = std::max(x1, static_cast<int>(last.base() - row) - 1);
    y0 = y0 < 0 ? v : y0, y1 = v;
  }
  if (x1 < 0) return {-1, -1, -1, -1};
  return {rect.x + x0, rect.y + y0, x1 - x0, y1 - y0};  // BOP: w = x_max - x_min
}

Image<uint8_t> ToFullImage(const std::vector<uint8_t>& mask, const PixelRect& rect, int width, int height, uint8_t value) {
  Image<uint8_t> image(width, height, 0);
  for (int v = 0; v < rect.height; ++v)
    for (int u = 0; u < rect.width; ++u)
      if (mask[static_cast<size_t>(v) * rect.width + u]) image.at(rect.x + u, rect.y + v) = value;
  return image;
}

std::vector<ObjectLabels> ComputeObjectLabels(const RenderOutput& render, const PinholeCamera& camera,
                                              const DepthImage* measured_depth_m, const VisibilityOptions& options) {
  options.check();
  MOCAP_CHECK(render.instance_ids.width == camera.width && render.instance_ids.height == camera.height,
              "render size differs from the camera's");
  if (measured_depth_m && (measured_depth_m->width != camera.width || measured_depth_m->height != camera.height))
    throw InputError("measured depth", Str("size ", measured_depth_m->width, "x", measured_depth_m->height,
                                           " differs from the camera's ", camera.width, "x", camera.height,
                                           " (register depth to the colour camera first)"));
  std::vector<ObjectLabels> labels;
  labels.reserve(render.layers.size());
  const double max_ray = MaxRayLength(camera);
  for (const ObjectLayer& layer : render.layers)
    labels.push_back(LabelOne(layer, render, camera, measured_depth_m, max_ray, options));
  return labels;
}

PoseFields MakePoseFields(const Rigid3d& T_camera_object) {
  return {T_camera_object.rvec(), T_camera_object.translation(), T_camera_object.quat_wxyz()};
}

}  // namespace mocap
