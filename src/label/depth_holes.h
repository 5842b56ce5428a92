#pragma once
// Judges a pixel without measured depth (a hole) on an object the model z-buffer shows nearest: is it
// the object, or an unmodelled occluder whose depth is missing? (VisibilityRule::kCombined,
// label/visibility.h, docs/labels.md "Depth holes".)
//
// The hole pixel looks along 8 directions (rows, columns, diagonals) for the first pixel with measured
// depth, up to hole_search_px away. Each such sample is
//  - explained when another modelled object is nearest there and the measurement agrees with its
//    render: that object is already in the z-buffer, so the sample tells nothing against this pixel;
//  - an occluder when it is nearer than the object (its render there, or at the hole pixel where the
//    object does not cover the sample) by more than delta: an unmodelled surface in front;
//  - a surface otherwise: the object itself, or something behind it.
// Then:
//  - no sample within reach (no depth at all, or a surface too near for the sensor): visible, as the
//    model says;
//  - only occluder samples: the hole is enclosed by a nearer surface (a dark patch on a hand, a hand's
//    part below the sensor's range): occluded;
//  - only surface or explained samples: the object's own hole, or a shadow on it: visible;
//  - both: occluded when the nearest occluder sample is at most hole_edge_px away (the occluder's own
//    edge pixels), or when the nearest surface sample is further than the widest shadow the occluder
//    can cast onto the object (fx * baseline * (1/z_occluder - 1/z), plus hole_edge_px); visible
//    otherwise.
// Structured-light and time-of-flight sensors lose depth at discontinuities on the far surface (the
// projector's and the camera's shadows) and in a pixel or so of the near one; the rule keeps the former
// on the object and gives the latter to the occluder. A hole wider than any shadow beside an occluder
// is the occluder's own surface without depth (a hand nearer than the sensor's range, in part): only the
// shadow's width next to the object stays the object's.
#include <vector>

#include "core/camera.h"
#include "core/image.h"
#include "label/visibility.h"
#include "render/renderer.h"

namespace mocap {

/// Length of the ray (x, y, 1) through pixel (u, v): converts z along the optical axis to the distance
/// from the camera centre, which is what BOP's visibility test compares.
double RayLength(const PinholeCamera& camera, int u, int v);

class HoleJudge {
 public:
  /// Preconditions: `measured_depth_m` and `render` have the camera's size; all outlive the judge.
  HoleJudge(const RenderOutput& render, const PinholeCamera& camera, const DepthImage& measured_depth_m,
            const VisibilityOptions& options);

  /// Whether hole pixel (u, v) of `layer`, rendered at z_m, is hidden by an unmodelled occluder.
  bool Occluded(const ObjectLayer& layer, int u, int v, float z_m) const;

 private:
  enum class Sample { kNone, kSurface, kOccluder };
  /// Classifies the measured sample at (x, y) against `layer` rendered at z_m at the hole pixel.
  Sample Classify(const ObjectLayer& layer, int x, int y, float z_m) const;
  /// Fills reach_: one pass over the image per direction, so that a hole pixel finds its samples in 8
  /// look-ups rather than walking up to hole_search_px pixels each way (a large hole, such as an object
  /// nearer than the sensor's range, would otherwise cost hundreds of steps per pixel).
  void FindReach() const;

  /// Per direction (kDirections), the steps from each pixel to the first pixel with measured depth; 0
  /// when there is none within hole_search_px. Built on the first hole judged (frames without holes on
  /// objects do not pay for it).
  mutable std::vector<Image<uint16_t>> reach_;
  const RenderOutput& render_;
  const PinholeCamera& camera_;
  const DepthImage& measured_;
  const VisibilityOptions& options_;
};

}  // namespace mocap
