#include "pipeline/build_info.h"

#include "mocap_build_info.h"

namespace mocap::pipeline {

const BuildInfo& CurrentBuildInfo() {
  static const BuildInfo info{MOCAP_VERSION, MOCAP_GIT_COMMIT, MOCAP_GIT_DIRTY != 0};
  return info;
}

}  // namespace mocap::pipeline
