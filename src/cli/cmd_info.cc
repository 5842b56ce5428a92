#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "core/check.h"
#include "session/reader.h"
#include "session/stats.h"

namespace mocap::cli {

int RunInfo(int argc, char** argv) {
  CLI::App app{"Summarise a session: frames, rates, gaps, dropouts, statuses, clock fits, missing files",
               "mocaplabel info"};
  std::string session;
  bool json = false;
  double gap_limit_s = 0.5;
  double max_interpolation_gap_s = 0.05;
  bool skip_corrupt = false;
  app.add_option("session", session, "session folder")->required();
  app.add_flag("--json", json, "print one JSON document");
  app.add_option("--gap-limit", gap_limit_s, "report spans between samples longer than this (s)")->capture_default_str();
  app.add_option("--max-interpolation-gap", max_interpolation_gap_s,
                 "longest span a camera pose is interpolated across (s)")->capture_default_str();
  app.add_flag("--skip-corrupt", skip_corrupt, "skip records that fail their checksum instead of stopping");
  CLI11_PARSE(app, argc, argv);
  if (!(gap_limit_s > 0) || !(max_interpolation_gap_s > 0))
    throw InputError("--gap-limit/--max-interpolation-gap", "must be positive seconds");

  SessionReaderOptions reader_options;
  reader_options.skip_corrupt_records = skip_corrupt;
  const SessionReader reader = SessionReader::Open(session, reader_options);
  SessionStatsOptions options;
  options.gap_limit_ns = std::llround(gap_limit_s * 1e9);
  options.interpolation.max_gap_ns = std::llround(max_interpolation_gap_s * 1e9);
  const SessionStats stats = ComputeSessionStats(reader, options);
  if (json) {
    std::printf("%s\n", ToJson(stats).dump(2).c_str());
  } else {
    std::fputs(FormatSessionStats(stats).c_str(), stdout);
  }
  return 0;
}

}  // namespace mocap::cli
