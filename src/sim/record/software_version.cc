#include "sim/record/software_version.h"

// Only this file includes the generated header (it also carries the git commit, which changes with
// every commit), so a new commit recompiles this file and nothing else of sim record.
#include "mocap_build_info.h"

namespace mocap::sim {

std::string SimSoftwareVersion() { return MOCAP_VERSION; }

}  // namespace mocap::sim
