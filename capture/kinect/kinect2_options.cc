#include "core/check.h"
#include "capture/kinect/kinect2_support.h"

namespace mocap::capture {

void Kinect2Options::check() const {
  if (!(min_depth_m > 0 && max_depth_m > min_depth_m))
    throw InputError("Kinect2Options", "need 0 < min_depth_m < max_depth_m");
  if (!pipeline.empty() && pipeline != "cpu" && pipeline != "opengl" && pipeline != "opencl" && pipeline != "cuda")
    throw InputError("Kinect2Options", "pipeline '" + pipeline + "' is not one of cpu, opengl, opencl, cuda");
  if (frame_timeout_ms <= 0) throw InputError("Kinect2Options", "frame_timeout_ms must be positive");
}

}  // namespace mocap::capture
