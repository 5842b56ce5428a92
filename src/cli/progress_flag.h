#pragma once
// The flags every long-running subcommand shares (docs/progress.md): --progress picks where progress
// goes, --log-level how much the log says. Both write to stderr; stdout keeps exactly the --json document.
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "core/progress.h"

namespace mocap::cli {

struct ProgressFlags {
  std::string progress = "auto";   // auto | terminal | json | none
  std::string log_level = "info";  // trace | debug | info | warn | error | critical | off
};

/// Adds --progress and --log-level to `app`, parsed into `flags`.
void AddProgressFlags(CLI::App& app, ProgressFlags& flags);

/// Sets the log's level and format (JSON lines with --progress json, so stderr is all JSON) and returns
/// the progress sink (nullptr for --progress none). InputError on an unknown mode or level.
std::unique_ptr<ProgressSink> ApplyProgressFlags(const ProgressFlags& flags);

}  // namespace mocap::cli
