#include "cli/progress_flag.h"

#include "core/log.h"
#include "pipeline/progress_sinks.h"

namespace mocap::cli {

void AddProgressFlags(CLI::App& app, ProgressFlags& flags) {
  // Checked by ApplyProgressFlags (InputError with the valid names), not by CLI11, so one message
  // format covers a bad flag here and a bad value from a config file later.
  app.add_option("--progress", flags.progress,
                 "progress on stderr: auto (a line on a terminal), terminal, json (one object per line; logs "
                 "become JSON lines too) or none")
      ->capture_default_str();
  app.add_option("--log-level", flags.log_level, "trace, debug, info, warn, error, critical or off")
      ->capture_default_str();
}

std::unique_ptr<ProgressSink> ApplyProgressFlags(const ProgressFlags& flags) {
  // Both parsed before anything changes, so a bad value leaves the log as it was.
  const ProgressMode mode = ProgressModeFromString(flags.progress);
  SetLogLevel(flags.log_level);
  SetLogJson(mode == ProgressMode::kJson);
  return MakeProgressSink(mode);
}

}  // namespace mocap::cli
