#include "capture/daemon/software_version.h"

// Only this file includes the generated header (it also carries the git commit, which changes with
// every commit), so a new commit recompiles this file and nothing else of the daemon.
#include "mocap_build_info.h"

namespace mocap::capture {

std::string CaptureSoftwareVersion() { return MOCAP_VERSION; }

}  // namespace mocap::capture
