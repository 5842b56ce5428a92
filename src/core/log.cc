#include "core/log.h"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/dist_sink.h>
#include <spdlog/sinks/stdout_sinks.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>

#include "core/check.h"

namespace mocap {
namespace {

constexpr const char* kTextPattern = "mocaplabel: [%l] %v";

/// Appends `text` to `out` as the body of a JSON string (quotes, backslashes and control bytes escaped;
/// other bytes, UTF-8 included, as they are).
void AppendJsonEscaped(std::string_view text, spdlog::memory_buf_t& out) {
  for (const char c : text) {
    switch (c) {
      case '"': out.append(std::string_view("\\\"")); break;
      case '\\': out.append(std::string_view("\\\\")); break;
      case '\n': out.append(std::string_view("\\n")); break;
      case '\r': out.append(std::string_view("\\r")); break;
      case '\t': out.append(std::string_view("\\t")); break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof(escaped), "\\u%04x", static_cast<unsigned>(c));
          out.append(std::string_view(escaped));
        } else {
          out.push_back(c);
        }
    }
  }
}

/// "2026-12-02T06:43:26.123Z": UTC with milliseconds, the form JavaScript's Date parses.
std::string TimeUtc(spdlog::log_clock::time_point time) {
  const auto since_epoch = time.time_since_epoch();
  const std::time_t seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch).count();
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(since_epoch).count() % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[64];  // room for any int the compiler assumes tm fields may hold
  std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", utc.tm_year + 1900, utc.tm_mon + 1,
                utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, static_cast<int>(ms));
  return text;
}

/// One compact JSON object per message, newline-terminated.
class JsonFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override {
    dest.append(std::string_view("{\"level\":\""));
    const spdlog::string_view_t level = spdlog::level::to_string_view(msg.level);
    dest.append(level.data(), level.data() + level.size());
    dest.append(std::string_view("\",\"msg\":\""));
    AppendJsonEscaped(std::string_view(msg.payload.data(), msg.payload.size()), dest);
    dest.append(std::string_view("\",\"time_utc\":\""));
    dest.append(TimeUtc(msg.time));
    dest.append(std::string_view("\"}\n"));
  }
  std::unique_ptr<spdlog::formatter> clone() const override { return std::make_unique<JsonFormatter>(); }
};

std::unique_ptr<spdlog::formatter> MakeFormatter(bool json) {
  if (json) return std::make_unique<JsonFormatter>();
  return std::make_unique<spdlog::pattern_formatter>(kTextPattern);
}

struct LogState {
  // The logger writes to one dist sink whose child is swapped (stderr, or a test's sink), so the
  // logger itself never changes and Log() references stay valid.
  std::shared_ptr<spdlog::sinks::dist_sink_mt> dist = std::make_shared<spdlog::sinks::dist_sink_mt>();
  spdlog::logger logger{"mocaplabel", dist};
  std::atomic<bool> json{false};

  LogState() {
    dist->set_sinks({std::make_shared<spdlog::sinks::stderr_sink_mt>()});
    logger.set_formatter(MakeFormatter(false));
    logger.set_level(spdlog::level::info);
    // Each message reaches the file at once: a cluster log is read while the job runs.
    logger.flush_on(spdlog::level::trace);
  }
};

LogState& State() {
  static LogState state;
  return state;
}

}  // namespace

spdlog::logger& Log() { return State().logger; }

void SetLogJson(bool json) {
  LogState& state = State();
  state.json = json;
  state.logger.set_formatter(MakeFormatter(json));
}

void SetLogLevel(std::string_view level) {
  static constexpr std::pair<std::string_view, spdlog::level::level_enum> kLevels[] = {
      {"trace", spdlog::level::trace}, {"debug", spdlog::level::debug}, {"info", spdlog::level::info},
      {"warn", spdlog::level::warn},   {"warning", spdlog::level::warn}, {"error", spdlog::level::err},
      {"critical", spdlog::level::critical}, {"off", spdlog::level::off}};
  for (const auto& [name, value] : kLevels) {
    if (name == level) {
      Log().set_level(value);
      return;
    }
  }
  throw InputError("--log-level", Str("unknown log level '", level,
                                      "': use trace, debug, info, warn, error, critical or off"));
}

void SetLogSinkForTest(std::shared_ptr<spdlog::sinks::sink> sink) {
  LogState& state = State();
  if (!sink) sink = std::make_shared<spdlog::sinks::stderr_sink_mt>();
  state.dist->set_sinks({std::move(sink)});
  // The dist sink hands its formatter to children only when it is set: set it again for the new child.
  state.logger.set_formatter(MakeFormatter(state.json));
}

}  // namespace mocap
