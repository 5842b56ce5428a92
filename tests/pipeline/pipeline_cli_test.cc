// `mocaplabel label`, `validate` and `info` as a user runs them: JSON progress lines on stderr, a killed
// run that leaves only <out>.partial, strict rig files refused with file:line and key, and `info RUN`
// telling whether a run is stale.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "tests/kinect/subprocess.h"
#include "tests/pipeline/synthetic_inputs.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

testing::ProcessResult Mocaplabel(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<std::string> argv = {MOCAPLABEL_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  return testing::RunProcess(argv, {{"MOCAPLABEL_CACHE_DIR", (log.parent_path() / "cache").string()}}, log);
}

std::vector<std::string> LabelArgs(const testing::Inputs& in, const fs::path& out) {
  return {"label", in.session.string(), "--rig", in.rig.string(), "--objects", in.objects.string(), "--out", out.string()};
}

TEST(PipelineCli, LabelProgressJsonCountsEveryFrame) {
  const testing::Inputs in = testing::MakeInputs("cli_progress", 40);
  std::vector<std::string> args = LabelArgs(in, in.dir / "L");
  args.insert(args.end(), {"--progress", "json", "--threads", "2"});
  const testing::ProcessResult r = Mocaplabel(args, in.dir / "log.txt");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::istringstream lines(r.output);
  int64_t last_done = -1, total = -1, reports = 0;
  bool finished = false;
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
    if (j.is_discarded() || !j.is_object() || j.value("progress", "") != "label") continue;
    ASSERT_FALSE(finished) << "a report after the finished one: " << line;
    EXPECT_GE(j["done"].get<int64_t>(), last_done) << line;
    last_done = j["done"].get<int64_t>();
    total = j["total"].get<int64_t>();
    EXPECT_EQ(j["unit"], "frames");
    finished = j["finished"].get<bool>();
    ++reports;
  }
  EXPECT_GE(reports, 2);
  EXPECT_EQ(total, 40);
  EXPECT_EQ(last_done, total);
  EXPECT_TRUE(finished);
}

TEST(PipelineCli, AKilledLabelRunLeavesOnlyItsPartialFolder) {
  const testing::Inputs in = testing::MakeInputs("cli_kill", 600);
  std::vector<std::string> argv = {MOCAPLABEL_EXE};
  for (const std::string& a : LabelArgs(in, in.dir / "L")) argv.push_back(a);
  argv.insert(argv.end(), {"--threads", "1", "--progress", "none"});
  testing::SpawnArgs spawn(argv, {{"MOCAPLABEL_CACHE_DIR", (in.dir / "cache").string()}});
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, spawn.args[0], nullptr, nullptr, spawn.args.data(), spawn.envp.data()), 0);
  const fs::path frames = in.dir / "L.partial" / "cam" / "instance";
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline &&
         !(fs::exists(frames) && std::distance(fs::directory_iterator(frames), fs::directory_iterator{}) >= 5))
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed; make the session longer";
  EXPECT_FALSE(fs::exists(in.dir / "L")) << "a killed run must not look finished";
  EXPECT_TRUE(fs::exists(in.dir / "L.partial"));
  // Running it again replaces the partial folder and publishes the run.
  const testing::ProcessResult again = Mocaplabel(LabelArgs(in, in.dir / "L"), in.dir / "again.txt");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(fs::exists(in.dir / "L" / "label_manifest.json"));
  EXPECT_TRUE(fs::exists(in.dir / "L" / "run.json"));
  EXPECT_FALSE(fs::exists(in.dir / "L.partial"));
}

/// The one line a failing command prints on stderr.
std::string ErrorLine(const testing::ProcessResult& r) {
  std::istringstream lines(r.output);
  std::string error;
  for (std::string line; std::getline(lines, line);)
    if (line.find("error:") != std::string::npos) error = line;
  return error;
}

TEST(PipelineCli, MisspeltRigAndObjectKeysAreRefusedWithFileLineAndKey) {
  const testing::Inputs in = testing::MakeInputs("cli_strict", 2);
  std::ifstream rig_in(in.rig);
  std::string rig((std::istreambuf_iterator<char>(rig_in)), {});
  rig.replace(rig.find("T_body_camera"), 13, "T_body_camra");
  std::ofstream(in.dir / "typo.yaml") << rig;
  std::vector<std::string> args = LabelArgs(in, in.dir / "L");
  args[3] = (in.dir / "typo.yaml").string();
  const testing::ProcessResult r = Mocaplabel(args, in.dir / "log.txt");
  EXPECT_NE(r.exit_code, 0);
  const std::string error = ErrorLine(r);
  EXPECT_NE(error.find((in.dir / "typo.yaml").string() + ":"), std::string::npos) << r.output;
  EXPECT_NE(error.find("'T_body_camra'"), std::string::npos) << r.output;
  EXPECT_NE(error.find("did you mean 'T_body_camera'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(in.dir / "L"));

  std::ifstream objects_in(in.objects);
  std::string objects((std::istreambuf_iterator<char>(objects_in)), {});
  objects.replace(objects.find("unit: m"), 7, "unit: inch");
  std::ofstream(in.dir / "bad_objects.yaml") << objects;
  args = LabelArgs(in, in.dir / "L");
  args[5] = (in.dir / "bad_objects.yaml").string();
  const std::string unit = ErrorLine(Mocaplabel(args, in.dir / "log2.txt"));
  EXPECT_NE(unit.find("bad_objects.yaml:"), std::string::npos) << unit;
  EXPECT_NE(unit.find("'unit'"), std::string::npos) << unit;
}

TEST(PipelineCli, InfoShowsARunsProvenanceAndWhetherItIsStale) {
  const testing::Inputs in = testing::MakeInputs("cli_info", 3);
  for (const auto& e : fs::recursive_directory_iterator(in.dir))
    if (e.is_regular_file()) fs::last_write_time(e.path(), fs::file_time_type::clock::now() - std::chrono::hours(1));
  ASSERT_EQ(Mocaplabel(LabelArgs(in, in.dir / "L"), in.dir / "label.txt").exit_code, 0);
  const testing::ProcessResult fresh = Mocaplabel({"info", (in.dir / "L").string(), "--json"}, in.dir / "info.txt");
  ASSERT_EQ(fresh.exit_code, 0) << fresh.output;
  const nlohmann::json j = nlohmann::json::parse(fresh.output.substr(fresh.output.find('{')));
  EXPECT_EQ(j["run"]["kind"], "label");
  EXPECT_FALSE(j["stale"]["stale"].get<bool>());
  fs::last_write_time(in.rig, fs::file_time_type::clock::now());  // touched: still up to date
  EXPECT_EQ(Mocaplabel({"info", (in.dir / "L").string(), "--check"}, in.dir / "touch.txt").exit_code, 0);
  std::ofstream(in.rig, std::ios::app) << "# a changed byte\n";
  const testing::ProcessResult stale = Mocaplabel({"info", (in.dir / "L").string(), "--check"}, in.dir / "stale.txt");
  EXPECT_EQ(stale.exit_code, 1) << stale.output;
  EXPECT_NE(stale.output.find("STALE"), std::string::npos) << stale.output;
  EXPECT_NE(stale.output.find("rig"), std::string::npos) << stale.output;
  // Against another rig file given on the command line.
  pipeline::Rig other = pipeline::ReadRig(in.rig);
  other.tracker_latency_ns += 1'000'000;
  pipeline::WriteRig(other, in.dir / "other.yaml");
  const testing::ProcessResult given =
      Mocaplabel({"info", (in.dir / "L").string(), "--rig", (in.dir / "other.yaml").string(), "--check"}, in.dir / "given.txt");
  EXPECT_EQ(given.exit_code, 1) << given.output;
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

size_t Lines(const std::string& text) { return static_cast<size_t>(std::count(text.begin(), text.end(), '\n')); }

TEST(PipelineCli, UsageErrorsAreOneLineWithOneStatus) {
  const testing::Inputs in = testing::MakeInputs("cli_usage", 1);
  const fs::path log = in.dir / "log.txt";
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"label"}, {"label", in.session.string(), "--max-gap-ms", "1e308"},
        {"label", in.session.string(), "--no-such-flag"}, {"validate", in.session.string(), "--threads", "x"},
        {"import", "tum"}, {"sim", "record"}, {"no-such-command"}}) {
    const testing::ProcessResult r = Mocaplabel(args, log);
    EXPECT_EQ(r.exit_code, 2) << args[0] << ": " << r.output;
    EXPECT_EQ(Lines(r.output), 1u) << r.output;
    EXPECT_NE(r.output.find("usage error"), std::string::npos) << r.output;
  }
  // The flag is named, not the struct it binds to (was "InterpolationOptions.max_gap_ns").
  const testing::ProcessResult gap = Mocaplabel({"label", in.session.string(), "--max-gap-ms", "1e308"}, log);
  EXPECT_NE(gap.output.find("--max-gap-ms"), std::string::npos) << gap.output;
  const testing::ProcessResult version = Mocaplabel({"--version"}, log);
  EXPECT_EQ(version.exit_code, 0) << version.output;
  EXPECT_EQ(version.output.rfind("mocaplabel ", 0), 0u) << version.output;
  EXPECT_EQ(Mocaplabel({"label", "--help"}, log).exit_code, 0);
}

TEST(PipelineCli, ValidateChecksTheObjectsNamedAndSaysWhenNoneWasLeft) {
  const testing::Inputs in = testing::MakeInputs("cli_validate_objects", 2);
  const fs::path log = in.dir / "log.txt";
  ASSERT_EQ(Mocaplabel(LabelArgs(in, in.dir / "L"), log).exit_code, 0);
  const std::vector<std::string> base = {"validate", in.session.string(), "--labels", (in.dir / "L").string(), "--objects",
                                         in.objects.string(), "--json"};
  auto validate = [&](std::vector<std::string> extra, const std::string& out) {
    std::vector<std::string> args = base;
    extra.insert(extra.end(), {"--out", (in.dir / out).string()});
    args.insert(args.end(), extra.begin(), extra.end());
    return Mocaplabel(args, log);
  };
  const testing::ProcessResult only = validate({"--objects-only", "box"}, "V1");
  ASSERT_EQ(only.exit_code, 0) << only.output;
  const nlohmann::json checked = nlohmann::json::parse(only.output.substr(only.output.rfind("\n{") + 1));
  EXPECT_EQ(checked["records"], 2) << only.output;
  const testing::ProcessResult skip = validate({"--skip-objects", "box"}, "V2");
  ASSERT_EQ(skip.exit_code, 0) << skip.output;
  const nlohmann::json none = nlohmann::json::parse(skip.output.substr(skip.output.rfind("\n{") + 1));
  EXPECT_EQ(none["records_checked"], 0);
  EXPECT_EQ(none["nothing_checked_why"], "all 2 label records with a pose were left out (by frame range, frame stride 1 or 1 objects left out)");
  // A misspelt name is an error naming the library, not a silent check of everything.
  const testing::ProcessResult typo = validate({"--skip-objects", "bx"}, "V3");
  EXPECT_EQ(typo.exit_code, 1) << typo.output;
  EXPECT_NE(typo.output.find(in.objects.string() + ": has no object 'bx'"), std::string::npos) << typo.output;
  EXPECT_FALSE(fs::exists(in.dir / "V3"));
  EXPECT_EQ(validate({"--skip-objects", "box", "--objects-only", "box"}, "V4").exit_code, 2);
}

TEST(PipelineCli, AnEmptyFileAtOutIsNeverReplaced) {
  const testing::Inputs in = testing::MakeInputs("cli_out_file", 1);
  const fs::path file = in.dir / "notes.txt";
  std::ofstream{file};
  const std::string shared = MOCAP_SHARED_DIR;
  ASSERT_EQ(Mocaplabel(LabelArgs(in, in.dir / "L"), in.dir / "label.txt").exit_code, 0);
  for (const std::vector<std::string>& args :
       {LabelArgs(in, file),
        {"validate", in.session.string(), "--labels", (in.dir / "L").string(), "--objects", in.objects.string(),
         "--out", file.string()},
        {"import", "tum", shared + "/realdata/tum_fr1_desk_9frames", "--out", file.string()},
        {"sim", "record", "--out", file.string()},
        {"demo", "--out", file.string()}}) {
    const testing::ProcessResult r = Mocaplabel(args, in.dir / "log.txt");
    EXPECT_NE(r.exit_code, 0) << args[0] << ": " << r.output;
    EXPECT_NE(r.output.find(file.string()), std::string::npos) << args[0] << ": " << r.output;
    ASSERT_TRUE(fs::is_regular_file(file)) << args[0] << " replaced the file";
  }
}

}  // namespace
}  // namespace mocap
