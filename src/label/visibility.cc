#include "label/visibility.h"

#include <cmath>

#include "core/check.h"

namespace mocap {

std::string_view ToString(VisibilityRule rule) { return rule == VisibilityRule::kBop19 ? "bop19" : "combined"; }

VisibilityRule ParseVisibilityRule(std::string_view text, const std::string& where) {
  if (text == "combined") return VisibilityRule::kCombined;
  if (text == "bop19") return VisibilityRule::kBop19;
  throw InputError(where, Str("unknown visibility rule '", text, "' (combined or bop19)"));
}

void VisibilityOptions::check() const {
  for (double value : {delta_base_m, noise_sigmas, noise_coeff_per_m, hole_shadow_baseline_m})
    if (!std::isfinite(value) || value < 0)
      throw InputError("visibility options",
                       Str("delta_base_m, noise_sigmas, noise_coeff_per_m and hole_shadow_baseline_m must be >= 0 (got ",
                           delta_base_m, ", ", noise_sigmas, ", ", noise_coeff_per_m, ", ", hole_shadow_baseline_m, ")"));
  if (hole_search_px < 1 || hole_search_px > 1000)
    throw InputError("visibility options", Str("hole_search_px must be in [1, 1000] (got ", hole_search_px, ")"));
  if (hole_edge_px < 0 || hole_edge_px > hole_search_px)
    throw InputError("visibility options",
                     Str("hole_edge_px must be in [0, hole_search_px] (got ", hole_edge_px, ")"));
  if (hole_colour_bins < 2 || hole_colour_bins > 256 || hole_colour_min_level < 0 || hole_colour_min_level > 255 ||
      hole_colour_min_reference_px < 1 || !(hole_colour_max_share >= 0 && hole_colour_max_share < 1))
    throw InputError("visibility options",
                     Str("hole colour test: bins must be in [2, 256], min_level in [0, 255], min_reference_px >= 1 "
                         "and max_share in [0, 1) (got ", hole_colour_bins, ", ", hole_colour_min_level, ", ",
                         hole_colour_min_reference_px, ", ", hole_colour_max_share, ")"));
}

}  // namespace mocap
