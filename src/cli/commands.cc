#include "cli/command.h"
#include "cli/commands.h"

namespace mocap::cli {

const std::vector<Command>& AllCommands() {
  static const std::vector<Command> commands = {
      {"version", "print the version", RunVersion},
      {"sim", "simulated rig: object meshes, scenario checks", RunSim},
  };
  return commands;
}

}  // namespace mocap::cli
