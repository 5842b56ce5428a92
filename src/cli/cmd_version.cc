#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"

namespace mocap::cli {

int RunVersion(int argc, char** argv) {
  CLI::App app{"Print the version of mocaplabel", "mocaplabel version"};
  bool json = false;
  app.add_flag("--json", json, "print one JSON document");
  MOCAP_PARSE(app, argc, argv);
  if (json) {
    std::printf("%s\n", nlohmann::json{{"version", MOCAP_VERSION}}.dump().c_str());
  } else {
    std::printf("mocaplabel %s\n", MOCAP_VERSION);
  }
  return 0;
}

}  // namespace mocap::cli
