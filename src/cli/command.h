#pragma once
// One binary, thin subcommands (DESIGN.md "CLI"). Each subcommand lives in its own cmd_<name>.cc,
// parses flags into the library's XxxOptions structs, calls the library, and prints its summary:
// with --json, stdout holds exactly one JSON document; progress and logs go to stderr.
#include <functional>
#include <string>
#include <vector>

namespace mocap::cli {

struct Command {
  std::string name;     ///< first word after `mocaplabel`
  std::string summary;  ///< one line for `mocaplabel --help`
  std::function<int(int argc, char** argv)> run;  ///< argv[0] is the subcommand name
};

/// Every subcommand, in the order `--help` lists them (commands.cc).
const std::vector<Command>& AllCommands();

}  // namespace mocap::cli
