#pragma once
// The process's one logging sink (DESIGN.md: library code reports through it, never with fprintf).
// Messages go to stderr, never stdout: stdout holds exactly the `--json` document a command prints.
// Text lines read "mocaplabel: [warning] ..."; in JSON mode each message is one line
// {"level":..,"msg":..,"time_utc":..} so a cluster log or web page can parse stderr alongside the JSON
// progress objects (src/pipeline/progress_sinks.h).
#include <spdlog/logger.h>

#include <memory>
#include <string_view>

namespace spdlog::sinks {
class sink;
}

namespace mocap {

/// The process logger "mocaplabel": stderr, info and above, text lines, until told otherwise.
/// Use it as Log().warn("session {} left incomplete: {}", dir, why) (fmt syntax).
spdlog::logger& Log();

/// One JSON object per message (true) or text lines "mocaplabel: [level] msg" (false, the default).
void SetLogJson(bool json);

/// trace, debug, info, warn (or warning), error, critical, off. InputError on any other name.
void SetLogLevel(std::string_view level);

/// Replaces where messages go (stderr by default; nullptr restores it), keeping the level and format.
/// For tests, which read what was logged from a file or an ostream sink.
void SetLogSinkForTest(std::shared_ptr<spdlog::sinks::sink> sink);

}  // namespace mocap
