#pragma once
// The entry point of each subcommand; each is defined in its cmd_<name>.cc.
#include <string>
#include <vector>

namespace mocap::cli {

int RunVersion(int argc, char** argv);
int RunInfo(int argc, char** argv);
int RunImport(int argc, char** argv);
int RunDoctor(int argc, char** argv);
int RunLabel(int argc, char** argv);
int RunNdiEmulator(int argc, char** argv);
int RunSim(int argc, char** argv);
int RunDevices(int argc, char** argv);
int RunValidate(int argc, char** argv);
int RunDemo(int argc, char** argv);
int RunCapture(int argc, char** argv);
int RunExport(int argc, char** argv);
int RunRelabel(int argc, char** argv);
int RunCalibrate(int argc, char** argv);

/// "mocaplabel <subcommand> <arguments...>" as a user typed it (argv[0] is the subcommand's name), for
/// the run.json of the runs a command writes.
std::vector<std::string> CommandLine(int argc, char** argv);

}  // namespace mocap::cli
