#include "cli/command.h"
#include "cli/commands.h"

namespace mocap::cli {

const std::vector<Command>& AllCommands() {
  static const std::vector<Command> commands = {
      {"version", "print the version", RunVersion},
      {"devices", "list attached Kinects, serial adapters and network trackers", RunDevices},
  };
  return commands;
}

}  // namespace mocap::cli
