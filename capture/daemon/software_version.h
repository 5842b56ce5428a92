#pragma once
// The mocaplabel version recorded in a captured session's manifest (`software_version`).
#include <string>

namespace mocap::capture {

/// CMake's PROJECT_VERSION, e.g. "0.1.0".
std::string CaptureSoftwareVersion();

}  // namespace mocap::capture
