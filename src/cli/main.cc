// mocaplabel: dispatches to the subcommand named by the first argument. Bad input reaches the user as
// one clear line on stderr and a non-zero exit status; internal errors abort with file:line.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "cli/command.h"
#include "core/check.h"

namespace {

void PrintUsage(std::FILE* out) {
  std::fprintf(out, "usage: mocaplabel <command> [options]   (mocaplabel <command> --help for its options)\n\ncommands:\n");
  for (const auto& command : mocap::cli::AllCommands())
    std::fprintf(out, "  %-12s %s\n", command.name.c_str(), command.summary.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    PrintUsage(stderr);
    return 2;  // usage error
  }
  const std::string name = argv[1];
  if (name == "--help" || name == "-h" || name == "help") {
    PrintUsage(stdout);
    return 0;
  }
  if (name == "--version" || name == "-V") {
    std::printf("mocaplabel %s\n", MOCAP_VERSION);
    return 0;
  }
  for (const auto& command : mocap::cli::AllCommands()) {
    if (command.name != name) continue;
    try {
      return command.run(argc - 1, argv + 1);
    } catch (const mocap::InputError& e) {
      std::fprintf(stderr, "mocaplabel %s: error: %s\n", name.c_str(), e.what());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "mocaplabel %s: error: %s\n", name.c_str(), e.what());
      return 1;
    }
  }
  // One line, as for every usage error (cli/parse_args.h); the command list is one --help away.
  std::fprintf(stderr, "mocaplabel: usage error: unknown command '%s' (see mocaplabel --help)\n", name.c_str());
  return 2;
}
