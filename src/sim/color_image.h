#pragma once
// 8-bit RGB pixels and images, as the renderer hands colour frames to the sensor models.
#include <array>
#include <cstdint>

#include "core/image.h"

namespace mocap::sim {

using Rgb8 = std::array<uint8_t, 3>;  ///< red, green, blue
using ColorImage = Image<Rgb8>;

}  // namespace mocap::sim
