#include "validate/validate_options.h"

#include "core/check.h"

namespace mocap {

void TrackingOptions::check() const {
  if (!(theta > 0 && theta <= 1)) throw InputError("TrackingOptions", "theta must lie in (0, 1]");
  if (!(box_margin_m >= 0)) throw InputError("TrackingOptions", "box_margin_m must be >= 0");
  if (reacquire_every < 0) throw InputError("TrackingOptions", "reacquire_every must be >= 0");
  if (!(confirm_fraction >= 0 && confirm_fraction <= 1)) throw InputError("TrackingOptions", "confirm_fraction must lie in [0, 1]");
  if (!(initial_gate_m > 0)) throw InputError("TrackingOptions", "initial_gate_m must be positive");
  if (!(max_gap_s > 0)) throw InputError("TrackingOptions", "max_gap_s must be positive");
  if (!(max_prior_distance_m > 0 && max_prior_angle_deg > 0))
    throw InputError("TrackingOptions", "max_prior_distance_m and max_prior_angle_deg must be positive");
  icp.check();
}

void VerdictOptions::check() const {
  if (!(accept_position_m > 0 && accept_position_m <= reject_position_m))
    throw InputError("VerdictOptions", "need 0 < accept_position_m <= reject_position_m");
  if (!(accept_rotation_deg > 0 && accept_rotation_deg <= reject_rotation_deg))
    throw InputError("VerdictOptions", "need 0 < accept_rotation_deg <= reject_rotation_deg");
  if (!(accept_floor_position_m > 0 && accept_floor_position_m <= accept_position_m))
    throw InputError("VerdictOptions", "need 0 < accept_floor_position_m <= accept_position_m");
  if (!(accept_floor_rotation_deg > 0 && accept_floor_rotation_deg <= accept_rotation_deg))
    throw InputError("VerdictOptions", "need 0 < accept_floor_rotation_deg <= accept_rotation_deg");
  if (!(accept_sigmas >= 0 && accept_sigmas <= 100)) throw InputError("VerdictOptions", "accept_sigmas must lie in [0, 100]");
  if (!(points_per_residual >= 1 && points_per_residual <= 1000))
    throw InputError("VerdictOptions", "points_per_residual must lie in [1, 1000]");
  if (!(success_position_m > 0 && success_rotation_deg > 0))
    throw InputError("VerdictOptions", "success thresholds must be positive");
  if (!(reject_label_score >= 0 && reject_label_score <= 1))
    throw InputError("VerdictOptions", "reject_label_score must lie in [0, 1]");
  if (min_supported_points < 0) throw InputError("VerdictOptions", "min_supported_points must be >= 0");
}

void ValidateOptions::check() const {
  if (!(scene_voxel_m >= 0)) throw InputError("ValidateOptions", "scene_voxel_m must be >= 0");
  if (!(occluder_margin_m >= 0)) throw InputError("ValidateOptions", "occluder_margin_m must be >= 0");
  if (min_scene_points < 3) throw InputError("ValidateOptions", "min_scene_points must be >= 3");
  alignment.check();
  crop.check();
  crop_cache.check();
  acquisition.check();
  tracking.check();
  filter.check();
  verdict.check();
  observability.check();
  outline.check();
  range_push.check();
  if (tracking.theta > acquisition.epsilon)
    throw InputError("ValidateOptions", "tracking.theta must not exceed acquisition.epsilon");
}

}  // namespace mocap
