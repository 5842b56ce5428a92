#include "cli/parse_args.h"

#include <cstdio>
#include <string>

namespace mocap::cli {

int ParseArgs(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return -1;
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --help-all: printed on stdout
    std::string message = e.what();
    for (char& c : message)
      if (c == '\n' || c == '\r') c = ' ';
    const std::string name = app.get_name().empty() ? "mocaplabel" : app.get_name();
    std::fprintf(stderr, "%s: usage error: %s (see %s --help)\n", name.c_str(), message.c_str(), name.c_str());
    return kUsageExitStatus;
  }
}

}  // namespace mocap::cli
