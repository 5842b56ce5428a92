#include "cli/command.h"
#include "cli/commands.h"

namespace mocap::cli {

const std::vector<Command>& AllCommands() {
  static const std::vector<Command> commands = {
      {"version", "print the version", RunVersion},
      {"ndi-emulator", "emulate an NDI tracker (Combined API) on loopback", RunNdiEmulator},
  };
  return commands;
}

}  // namespace mocap::cli
