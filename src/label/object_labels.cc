#include "label/object_labels.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <optional>

#include "core/check.h"
#include "label/depth_holes.h"

namespace mocap {
namespace {

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

/// The measured-depth decision of one amodal pixel under the options' rule.
struct MeasuredRule {
  const PinholeCamera& camera;
  const VisibilityOptions& options;
  const HoleJudge* holes;  ///< null under kBop19
  double max_ray;
  const HoleColours* colours;  ///< the colour test on holes: null when off or without a colour image

  bool Visible(const ObjectLayer& layer, int u, int v, float z, float z_measured, bool nearest_in_model) const {
    if (options.rule == VisibilityRule::kBop19) return VisibleInMeasured(camera, u, v, z, z_measured, max_ray, options);
    if (!nearest_in_model) return false;  // a modelled object hides it, with or without depth
    if (z_measured > 0.0f) return VisibleInMeasured(camera, u, v, z, z_measured, max_ray, options);
    return !holes->Occluded(layer, u, v, z);
  }
};

/// Pixel counts of one object's masks.
struct MaskCounts {
  int inside = 0, visible_model = 0, valid = 0, visible_measured = 0, visible_assumed = 0;
};

MaskCounts FillMasks(const ObjectLayer& layer, const RenderOutput& render, const DepthImage* measured,
                     const MeasuredRule& rule, ObjectMasks& m) {
  MaskCounts c;
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
      amodal[k] = 1, ++c.inside;
      if (id_row[k] == layer.instance_id) model[k] = 1, ++c.visible_model;
      if (!measured_row) continue;
      const float zm = measured_row[k];
      c.valid += zm > 0.0f;
      if (!rule.Visible(layer, m.rect.x + k, v, z, zm, model[k] != 0)) continue;
      consistent[k] = 1;
      ++(zm > 0.0f ? c.visible_measured : c.visible_assumed);
    }
  }
  return c;
}

ObjectLabels LabelOne(const ObjectLayer& layer, const RenderOutput& render, const DepthImage* measured,
                      const MeasuredRule& rule) {
  ObjectLabels out;
  ObjectMasks& m = out.masks;
  ObjectStats& s = out.stats;
  m.instance_id = s.instance_id = layer.instance_id;
  m.rect = layer.rect;
  const size_t n = layer.depth_m.size();
  m.amodal.assign(n, 0);
  m.visible_model.assign(n, 0);
  if (measured) m.visible_measured.assign(n, 0);
  MaskCounts c = FillMasks(layer, render, measured, rule, m);
  // Only visible pixels without depth can be foreign: an object with none skips the colour pass.
  if (measured && rule.colours && c.visible_assumed > 0)
    c.visible_assumed -= HideForeignHoles(layer.instance_id, m.rect, *measured, *rule.colours, rule.options, m.visible_measured);
  s.bbox_obj = layer.bbox_obj;
  s.px_count_all = layer.px_count_all;
  s.truncated_by_canvas = layer.truncated_by_canvas;
  s.outside_image = c.inside == 0;
  s.px_count_visib_model = c.visible_model;
  s.visib_fract_model = s.px_count_all > 0 ? static_cast<double>(c.visible_model) / s.px_count_all : 0.0;
  s.px_count_valid = measured ? c.valid : -1;
  s.px_count_visib = measured ? c.visible_measured + c.visible_assumed : c.visible_model;
  s.visib_fract = s.px_count_all > 0 ? static_cast<double>(s.px_count_visib) / s.px_count_all : 0.0;
  if (measured) {
    s.px_count_visib_measured = c.visible_measured, s.px_count_visib_assumed = c.visible_assumed;
    s.mask_confidence = s.px_count_visib > 0 ? static_cast<double>(c.visible_measured) / s.px_count_visib : 1.0;
  }
  s.bbox_visib = MaskBox(measured ? m.visible_measured : m.visible_model, m.rect);
  return out;
}

}  // namespace

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
                                              const DepthImage* measured_depth_m, const VisibilityOptions& options,
                                              const HoleColours* colours) {
  options.check();
  MOCAP_CHECK(render.instance_ids.width == camera.width && render.instance_ids.height == camera.height,
              "render size differs from the camera's");
  if (measured_depth_m && (measured_depth_m->width != camera.width || measured_depth_m->height != camera.height))
    throw InputError("measured depth", Str("size ", measured_depth_m->width, "x", measured_depth_m->height,
                                           " differs from the camera's ", camera.width, "x", camera.height,
                                           " (register depth to the colour camera first)"));
  if (colours && (colours->image.width != camera.width || colours->image.height != camera.height))
    throw InputError("colour image", Str("size ", colours->image.width, "x", colours->image.height, " differs from the camera's ",
                                         camera.width, "x", camera.height));
  std::vector<ObjectLabels> labels;
  labels.reserve(render.layers.size());
  std::optional<HoleJudge> holes;
  if (measured_depth_m && options.rule == VisibilityRule::kCombined)
    holes.emplace(render, camera, *measured_depth_m, options);
  const bool colour_test = holes && options.hole_colour && colours;
  const MeasuredRule rule{camera, options, holes ? &*holes : nullptr, MaxRayLength(camera), colour_test ? colours : nullptr};
  for (const ObjectLayer& layer : render.layers) labels.push_back(LabelOne(layer, render, measured_depth_m, rule));
  return labels;
}

PoseFields MakePoseFields(const Rigid3d& T_camera_object) {
  return {T_camera_object.rvec(), T_camera_object.translation(), T_camera_object.quat_wxyz()};
}

}  // namespace mocap
