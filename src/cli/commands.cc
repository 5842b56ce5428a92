#include "cli/command.h"
#include "cli/commands.h"

namespace mocap::cli {

const std::vector<Command>& AllCommands() {
  static const std::vector<Command> commands = {
      {"version", "print the version", RunVersion},
      {"doctor", "check headless rendering (EGL platform, driver, test render)", RunDoctor},
  };
  return commands;
}

}  // namespace mocap::cli
