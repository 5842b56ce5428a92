#pragma once
// Surfaces that give a depth sensor no return in places: dark (too little infrared comes back) or shiny
// (the projected pattern or the modulated light is mirrored away). A scenario marks an object or an
// occluder with `depth_loss`, the fraction of its visible surface without depth; the loss comes in square
// patches (a highlight, a dark print), drawn afresh each frame. A phenomenological model for exercising
// the labeller's treatment of depth holes, not one fitted to a material.
#include <cstdint>
#include <vector>

#include "core/image.h"

namespace mocap::sim {

struct DepthLoss {
  /// Per instance id of the clean render: the fraction of its pixels without depth, in [0, 1].
  std::vector<std::pair<uint16_t, double>> fraction_by_instance;
  int patch_px = 6;  ///< side of the square patches that lose their depth together

  bool empty() const { return fraction_by_instance.empty(); }
  /// Whether pixel (u, v), showing `instance`, loses its depth in the frame drawn with `seed`.
  bool Lost(int u, int v, uint16_t instance, uint64_t seed) const;
  /// Throws InputError for a fraction outside [0, 1] or a patch smaller than one pixel.
  void check() const;
};

}  // namespace mocap::sim
