#include "session/depth_in_color.h"

#include "core/check.h"
#include "core/depth_registration.h"

namespace mocap {

DepthInColor DepthInColor::Of(const CameraStreamInfo& info, const PinholeCamera& color_camera,
                              const std::optional<Rigid3d>& T_color_depth) {
  DepthInColor out;
  out.registered = info.depth_registered_to_color;
  out.depth_camera = info.depth_camera;
  out.color_camera = color_camera;
  out.T_color_depth = T_color_depth.value_or(info.T_color_depth);
  return out;
}

DepthImage DepthInColor::ToColor(DepthImage depth_m) const {
  const PinholeCamera& stored = registered ? color_camera : depth_camera;
  if (depth_m.width != stored.width || depth_m.height != stored.height)
    throw InputError("measured depth", Str("size ", depth_m.width, "x", depth_m.height, " differs from the ",
                                           registered ? "colour" : "depth", " camera's ", stored.width, "x",
                                           stored.height));
  if (registered) return depth_m;  // moved out: no copy
  return RegisterDepthToColor(depth_m, depth_camera, color_camera, T_color_depth);
}

DepthImage LoadDepthInColor(const SessionReader& session, const std::string& camera, int64_t index,
                            const DepthInColor& registration) {
  return registration.ToColor(session.LoadDepth(camera, index));
}

}  // namespace mocap
