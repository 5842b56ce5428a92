#pragma once
// Where progress goes (docs/progress.md): a line redrawn in place on a terminal, or one JSON object per
// line for a web page or a cluster log. Both write to stderr by default: stdout holds exactly the
// `--json` document a command prints.
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "core/progress.h"

namespace mocap {

/// "label  120/300 frames  45.1 frames/s  4 s left", redrawn with '\r' when `out` is a terminal and
/// ended with a newline when the task finishes. When `out` is not a terminal (a log file, CI output) only
/// the final line is printed, so logs stay free of carriage returns.
class TerminalProgressSink final : public ProgressSink {
 public:
  explicit TerminalProgressSink(FILE* out = stderr);
  void Report(const ProgressUpdate& update) override;

 private:
  FILE* out_;
  bool is_terminal_;
  std::mutex mutex_;
};

/// The line TerminalProgressSink draws for `update` (no '\r', no newline).
std::string FormatProgressLine(const ProgressUpdate& update);

/// One compact JSON object per update, one per line, flushed at once:
/// {"progress":task,"done":..,"total":..,"unit":..,"elapsed_s":..,"rate_per_s":..,"eta_s":..|null,
///  "finished":..}.
class JsonProgressSink final : public ProgressSink {
 public:
  explicit JsonProgressSink(FILE* out = stderr);
  void Report(const ProgressUpdate& update) override;

 private:
  FILE* out_;
  std::mutex mutex_;
};

enum class ProgressMode { kAuto, kTerminal, kJson, kNone };

/// "auto", "terminal", "json" or "none"; InputError on anything else.
ProgressMode ProgressModeFromString(std::string_view mode);

/// auto and terminal: a TerminalProgressSink on stderr (which prints only final lines when stderr is not
/// a terminal); json: a JsonProgressSink on stderr; none: nullptr (Progress then does nothing).
std::unique_ptr<ProgressSink> MakeProgressSink(ProgressMode mode);

}  // namespace mocap
