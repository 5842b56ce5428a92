#pragma once
// The tool's version and the commit it was built from, as recorded in every run.json. Only
// build_info.cc includes the generated header, so a new commit recompiles one file.
#include <string>

namespace mocap::pipeline {

struct BuildInfo {
  std::string version;     ///< project version from CMakeLists.txt, e.g. "0.1.0"
  std::string git_commit;  ///< `git rev-parse HEAD` at build time; "" when not built from a checkout
  bool git_dirty = false;  ///< tracked files differed from the commit at build time
};

/// Build info of this binary (generated at build time by cmake/BuildInfo.cmake).
const BuildInfo& CurrentBuildInfo();

}  // namespace mocap::pipeline
