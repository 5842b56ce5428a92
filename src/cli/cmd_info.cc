// mocaplabel info S | RUN: a session's frames, rates, gaps, dropouts and clock fits; or a run folder's
// provenance (run.json: command, version, inputs) and whether it is stale against its inputs
// (docs/provenance.md).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "cli/parse_args.h"
#include "cli/commands.h"
#include "core/check.h"
#include "pipeline/provenance.h"
#include "session/reader.h"
#include "session/stats.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

struct RunFlags {
  std::string session, rig, objects, labels;
  std::vector<std::string> meshes;  ///< NAME=PATH
  bool check = false;
};

std::map<std::string, fs::path> Overrides(const RunFlags& flags) {
  std::map<std::string, fs::path> overrides;
  if (!flags.session.empty()) overrides["session"] = flags.session;
  if (!flags.rig.empty()) overrides["rig"] = flags.rig;
  if (!flags.objects.empty()) overrides["objects"] = flags.objects;
  if (!flags.labels.empty()) overrides["labels"] = flags.labels;
  for (const std::string& mesh : flags.meshes) {
    const size_t eq = mesh.find('=');
    if (eq == std::string::npos || eq == 0) throw InputError("--mesh " + mesh, "expected NAME=PATH (an object's name and a mesh file)");
    overrides["mesh:" + mesh.substr(0, eq)] = mesh.substr(eq + 1);
  }
  return overrides;
}

void PrintRun(const pipeline::RunProvenance& run, const pipeline::StaleReport& stale) {
  std::string command;
  for (const std::string& arg : run.command) command += (command.empty() ? "" : " ") + arg;
  std::printf("%s run, made %s by mocaplabel %s%s%s\n", run.kind.c_str(), run.created_utc.c_str(), run.tool_version.c_str(),
              run.git_commit.empty() ? "" : (" (" + run.git_commit.substr(0, 12) + (run.git_dirty ? ", modified" : "") + ")").c_str(),
              command.empty() ? "" : ("\n  command: " + command).c_str());
  if (!run.shard.is_null()) std::printf("  shard: %s\n", run.shard.dump().c_str());
  for (const pipeline::InputRecord& input : run.inputs)
    std::printf("  %-22s %s (%s%s)\n", input.role.c_str(), input.path.c_str(), input.hash.substr(0, 16).c_str(),
                input.tree ? Str(", ", input.files, " files").c_str() : "");
  if (!stale.stale) {
    std::printf("up to date: every input is as the run read it (%lld files checked, %lld hashed, %.3f s)\n",
                static_cast<long long>(stale.files_checked), static_cast<long long>(stale.files_hashed), stale.seconds);
    return;
  }
  std::printf("STALE:\n");
  for (const pipeline::InputChange& change : stale.changes)
    std::printf("  %s %s: %s\n", change.role.c_str(), change.path.c_str(), change.what.c_str());
}

int RunInfoOfRun(const fs::path& dir, const RunFlags& flags, bool json) {
  const pipeline::RunProvenance run = pipeline::ReadRunJson(dir);
  pipeline::HashCache cache;
  const pipeline::StaleReport stale = pipeline::CheckStale(run, Overrides(flags), cache);
  if (json) std::printf("%s\n", nlohmann::json{{"run", pipeline::ToJson(run)}, {"stale", pipeline::ToJson(stale)}}.dump().c_str());
  else PrintRun(run, stale);
  return flags.check && stale.stale ? 1 : 0;
}

}  // namespace

int RunInfo(int argc, char** argv) {
  CLI::App app{"Summarise a session (frames, rates, gaps, dropouts, statuses, clock fits, missing files), or show a run's "
               "provenance and whether it is stale", "mocaplabel info"};
  std::string path;
  bool json = false;
  double gap_limit_s = 0.5;
  double max_interpolation_gap_s = 0.05;
  bool skip_corrupt = false;
  RunFlags run;
  app.add_option("path", path, "session folder, or a run folder (one holding run.json: label, validation, demo)")->required();
  app.add_flag("--json", json, "print one JSON document");
  app.add_option("--gap-limit", gap_limit_s, "report spans between samples longer than this (s)")
      ->capture_default_str()->check(CLI::Range(1e-6, 86400.0));
  app.add_option("--max-interpolation-gap", max_interpolation_gap_s,
                 "longest span a camera pose is interpolated across (s)")
      ->capture_default_str()->check(CLI::Range(1e-6, 86400.0));
  app.add_flag("--skip-corrupt", skip_corrupt, "skip records that fail their checksum instead of stopping");
  app.add_option("--session", run.session, "run: compare with this session instead of the one it read");
  app.add_option("--rig", run.rig, "run: compare with this rig file");
  app.add_option("--objects", run.objects, "run: compare with this object library");
  app.add_option("--labels", run.labels, "run: compare with this label run");
  app.add_option("--mesh", run.meshes, "run: compare object NAME's mesh with this file (NAME=PATH, repeatable)");
  app.add_flag("--check", run.check, "run: exit with status 1 when the run is stale");
  MOCAP_PARSE(app, argc, argv);
  if (fs::exists(fs::path(path) / "run.json")) return RunInfoOfRun(path, run, json);

  SessionReaderOptions reader_options;
  reader_options.skip_corrupt_records = skip_corrupt;
  const SessionReader reader = SessionReader::Open(path, reader_options);
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
