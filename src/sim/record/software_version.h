#pragma once
// The mocaplabel version recorded in a simulated session's manifest (`software_version`).
#include <string>

namespace mocap::sim {

/// CMake's PROJECT_VERSION, e.g. "0.1.0".
std::string SimSoftwareVersion();

}  // namespace mocap::sim
