#include "cli/command.h"
#include "cli/commands.h"

namespace mocap::cli {

const std::vector<Command>& AllCommands() {
  static const std::vector<Command> commands = {
      {"version", "print the version", RunVersion},
      {"info", "summarise a session: frames, rates, gaps, dropouts, clock fits", RunInfo},
      {"import", "import tum|plus|motive|bop recordings into a session", RunImport},
      {"label", "label every frame: masks, rendered depth, poses and flags", RunLabel},
      {"doctor", "check headless rendering (EGL platform, driver, test render)", RunDoctor},
      {"ndi-emulator", "emulate an NDI tracker (Combined API) on loopback", RunNdiEmulator},
      {"sim", "simulated rig: object meshes, scenario checks", RunSim},
      {"demo", "the whole tool on the simulated rig: simulate, label, score against the truth", RunDemo},
      {"devices", "list attached Kinects, serial adapters and network trackers", RunDevices},
      {"export", "export labelled sessions as a dataset: BOP, COCO with poses, segmentation pairs, TUM", RunExport},
      {"validate", "check every label against the measured depth (SegICP): verdicts and a report", RunValidate},
      {"calibrate", "calibrate the rig from a session: board, intrinsics, camera-mount, latency, depth-to-color, pivot, object-mount, check", RunCalibrate},
      {"relabel", "label, validate and export again what is stale, on all cores or on a Slurm cluster", RunRelabel},
      {"capture", "capture daemon and its control: daemon, start, stop, status", RunCapture},
  };
  return commands;
}

std::vector<std::string> CommandLine(int argc, char** argv) {
  std::vector<std::string> command = {"mocaplabel"};
  command.insert(command.end(), argv, argv + argc);
  return command;
}

}  // namespace mocap::cli
