#pragma once
// Per-object masks and BOP statistics of one frame, from a render (render/renderer.h) and, when there is
// one, the measured depth. No file I/O here.
//
// Three masks per object (docs/labels.md):
//  - amodal: the object rendered alone (BOP `mask`); includes pixels hidden by other objects;
//  - visible_model: pixels where this object is the nearest rendered object (the z-buffer); the
//    visible_model masks of all objects and the background partition the image;
//  - visible_measured: visible by the measured depth under VisibilityOptions::rule (label/visibility.h):
//    by default the combined rule (a subset of visible_model: measured depth removes unmodelled
//    occluders such as hands, depth holes are judged from their surroundings); with kBop19 BOP19's
//    `mask_visib` exactly (may overlap between objects).
#include <array>
#include <cstdint>
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "core/rigid3.h"
#include "label/hole_colour.h"
#include "label/visibility.h"
#include "render/renderer.h"

namespace mocap {

/// [x, y, w, h] in pixels as BOP writes it (bop_toolkit misc.calc_2d_bbox): x, y = the first covered
/// column and row, w = x_max - x_min, h = y_max - y_min (so one pixel has w = 0; COCO-style extents are
/// w + 1); {-1, -1, -1, -1} when empty.
using PixelBox = std::array<int, 4>;

/// Masks of one object over `rect` (image pixels); each is rect.width * rect.height bytes, 1 = in.
struct ObjectMasks {
  uint16_t instance_id = 0;
  PixelRect rect;
  std::vector<uint8_t> amodal, visible_model, visible_measured;  ///< visible_measured empty without depth

  bool at(const std::vector<uint8_t>& mask, int u, int v) const {
    return rect.contains(u, v) && mask[static_cast<size_t>(v - rect.y) * rect.width + (u - rect.x)] != 0;
  }
};

/// BOP's scene_gt_info fields and more, for one object (formats.md §1).
struct ObjectStats {
  uint16_t instance_id = 0;
  PixelBox bbox_obj{-1, -1, -1, -1};    ///< amodal, including parts outside the image
  PixelBox bbox_visib{-1, -1, -1, -1};  ///< of the visible mask (measured when depth is given, else model)
  int px_count_all = 0;                 ///< amodal pixels, including outside the image
  int px_count_valid = -1;              ///< amodal pixels with measured depth > 0; -1 without measured depth
  int px_count_visib = 0;               ///< visible pixels (same choice as bbox_visib)
  double visib_fract = 0;               ///< px_count_visib / px_count_all; 0 when px_count_all is 0
  /// Of the visible pixels (measured depth given): those whose measured depth agrees with the render
  /// (measured), and those without depth, visible by the hole rule or the model (assumed). -1 without
  /// measured depth.
  int px_count_visib_measured = -1, px_count_visib_assumed = -1;
  /// px_count_visib_measured / px_count_visib: how much of the visible mask the depth confirms (1 when
  /// nothing is visible); -1 without measured depth.
  double mask_confidence = -1;
  int px_count_visib_model = 0;         ///< pixels where the object is nearest (z-buffer)
  double visib_fract_model = 0;
  bool truncated_by_canvas = false;     ///< extends beyond the render canvas: counts are lower bounds
  bool outside_image = false;           ///< no amodal pixel inside the image
};

struct ObjectLabels {
  ObjectMasks masks;
  ObjectStats stats;
};

/// Computes masks and statistics for every rendered object. `measured_depth_m` may be null (no depth);
/// otherwise it must have the camera's size and be registered to it (depth in the colour camera).
/// `colours` (may be null) is the frame's colour image and the objects' mesh colours, used only by the
/// optional colour test on holes (VisibilityOptions::hole_colour, label/hole_colour.h). Throws
/// InputError when the measured depth's or the colour image's size differs from the camera's.
std::vector<ObjectLabels> ComputeObjectLabels(const RenderOutput& render, const PinholeCamera& camera,
                                              const DepthImage* measured_depth_m, const VisibilityOptions& options = {},
                                              const HoleColours* colours = nullptr);

/// Bounding box of the set pixels of a rect-sized mask, in image pixels.
PixelBox MaskBox(const std::vector<uint8_t>& mask, const PixelRect& rect);

/// A rect-sized mask placed into a full image (0 / value).
Image<uint8_t> ToFullImage(const std::vector<uint8_t>& mask, const PixelRect& rect, int width, int height,
                           uint8_t value = 255);

/// The pose fields written for users: object (mesh) to camera, OpenCV axes.
struct PoseFields {
  Eigen::Vector3d rvec;       ///< Rodrigues vector, radians, angle in [0, pi]
  Eigen::Vector3d t_m;        ///< translation, metres
  Eigen::Vector4d quat_wxyz;  ///< w >= 0
};
PoseFields MakePoseFields(const Rigid3d& T_camera_object);

}  // namespace mocap
