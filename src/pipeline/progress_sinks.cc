#include "pipeline/progress_sinks.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/check.h"

namespace mocap {
namespace {

/// "4 s", "3 min 20 s", "2 h 05 min": coarse enough not to flicker while the rate settles.
std::string FormatDuration(double seconds) {
  const int64_t s = std::llround(std::max(0.0, seconds));
  char text[48];
  if (s < 60) {
    std::snprintf(text, sizeof(text), "%lld s", static_cast<long long>(s));
  } else if (s < 3600) {
    std::snprintf(text, sizeof(text), "%lld min %02lld s", static_cast<long long>(s / 60),
                  static_cast<long long>(s % 60));
  } else {
    std::snprintf(text, sizeof(text), "%lld h %02lld min", static_cast<long long>(s / 3600),
                  static_cast<long long>(s % 3600 / 60));
  }
  return text;
}

}  // namespace

std::string FormatProgressLine(const ProgressUpdate& update) {
  std::string line = update.task + "  " + std::to_string(update.done);
  if (update.total > 0) line += "/" + std::to_string(update.total);
  line += " " + update.unit;
  char rate[64];
  std::snprintf(rate, sizeof(rate), "  %.1f %s/s", update.rate_per_s, update.unit.c_str());
  line += rate;
  if (update.finished) {
    line += "  done in " + FormatDuration(update.elapsed_s);
  } else if (update.eta_s >= 0) {
    line += "  " + FormatDuration(update.eta_s) + " left";
  }
  return line;
}

TerminalProgressSink::TerminalProgressSink(FILE* out) : out_(out), is_terminal_(isatty(fileno(out)) == 1) {}

void TerminalProgressSink::Report(const ProgressUpdate& update) {
  if (!is_terminal_ && !update.finished) return;
  const std::string line = FormatProgressLine(update);
  std::lock_guard lock(mutex_);
  if (is_terminal_) {
    // Back to the line's start, the new text, then clear what a longer previous line left behind.
    std::fprintf(out_, "\r%s\033[K%s", line.c_str(), update.finished ? "\n" : "");
  } else {
    std::fprintf(out_, "%s\n", line.c_str());
  }
  std::fflush(out_);
}

JsonProgressSink::JsonProgressSink(FILE* out) : out_(out) {}

void JsonProgressSink::Report(const ProgressUpdate& update) {
  nlohmann::ordered_json object = {{"progress", update.task},
                           {"done", update.done},
                           {"total", update.total},
                           {"unit", update.unit},
                           {"elapsed_s", update.elapsed_s},
                           {"rate_per_s", update.rate_per_s},
                           {"eta_s", nullptr},
                           {"finished", update.finished}};
  if (update.eta_s >= 0) object["eta_s"] = update.eta_s;
  // ordered_json keeps the documented field order; bad UTF-8 in a task name is replaced, not thrown.
  const std::string line = object.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
  std::lock_guard lock(mutex_);
  std::fwrite(line.data(), 1, line.size(), out_);
  std::fflush(out_);
}

ProgressMode ProgressModeFromString(std::string_view mode) {
  if (mode == "auto") return ProgressMode::kAuto;
  if (mode == "terminal") return ProgressMode::kTerminal;
  if (mode == "json") return ProgressMode::kJson;
  if (mode == "none") return ProgressMode::kNone;
  throw InputError("--progress", Str("unknown progress mode '", mode, "': use auto, terminal, json or none"));
}

std::unique_ptr<ProgressSink> MakeProgressSink(ProgressMode mode) {
  switch (mode) {
    case ProgressMode::kAuto:
    case ProgressMode::kTerminal: return std::make_unique<TerminalProgressSink>(stderr);
    case ProgressMode::kJson: return std::make_unique<JsonProgressSink>(stderr);
    case ProgressMode::kNone: return nullptr;
  }
  return nullptr;
}

}  // namespace mocap
