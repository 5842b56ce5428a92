#pragma once
// Command-line parsing with the project's error convention: a usage error (unknown flag, missing
// argument, value out of range) is one line on stderr naming the command and exit status 2, for every
// command (docs/cli.md "Exit status"). CLI11's own macro prints two lines and returns codes 104-114.
#include <CLI/CLI.hpp>

namespace mocap::cli {

/// Exit status of a usage error (as for an unknown command).
inline constexpr int kUsageExitStatus = 2;

/// Parses; returns -1 to go on, or the status to exit with (0 after --help).
int ParseArgs(CLI::App& app, int argc, char** argv);

}  // namespace mocap::cli

/// Parses or returns from the calling command (use in place of CLI11_PARSE).
#define MOCAP_PARSE(app, argc, argv)                                              \
  if (const int mocap_parse_status = ::mocap::cli::ParseArgs(app, argc, argv);    \
      mocap_parse_status >= 0)                                                    \
  return mocap_parse_status
