#include "sim/depth_loss.h"

#include "core/check.h"
#include "sim/rng.h"

namespace mocap::sim {

bool DepthLoss::Lost(int u, int v, uint16_t instance, uint64_t seed) const {
  if (instance == 0) return false;
  for (const auto& [id, fraction] : fraction_by_instance) {
    if (id != instance) continue;
    // One draw per patch and instance: the patch's pixels lose their depth together.
    const auto patch_u = static_cast<uint64_t>(u / patch_px), patch_v = static_cast<uint64_t>(v / patch_px);
    Rng rng = Rng::Derive(seed ^ 0xda4c5u, (static_cast<uint64_t>(id) << 40) ^ (patch_u << 20) ^ patch_v);
    return rng.Bernoulli(fraction);
  }
  return false;
}

void DepthLoss::check() const {
  if (patch_px < 1) throw InputError("depth_loss", Str("patch size must be >= 1 pixel (got ", patch_px, ")"));
  for (const auto& [id, fraction] : fraction_by_instance)
    if (!(fraction >= 0 && fraction <= 1))
      throw InputError("depth_loss", Str("instance ", id, ": fraction ", fraction, " is not in [0, 1]"));
}

}  // namespace mocap::sim
