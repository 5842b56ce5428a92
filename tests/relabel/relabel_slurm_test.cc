// `mocaplabel relabel --executor slurm` on a real single-node Slurm cluster (tests/slurm starts it:
// Debian's munge, slurmctld and slurmd on loopback): the same runs and dataset as the local executor;
// a shard cancelled with scancel mid-run reported with its log, and a rerun that redoes only it; a
// refused or unreachable sbatch is one clear error and leaves nothing behind.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "pipeline/subprocess.h"
#include "tests/relabel/relabel_fixture.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::Mocaplabel;

std::vector<std::string> Relabel(const std::vector<fs::path>& sessions, const fs::path& dir, const testing::RelabelSessions& s,
                                 std::vector<std::string> extra) {
  std::vector<std::string> args = {"relabel"};
  for (const fs::path& session : sessions) args.push_back(session.string());
  args.insert(args.end(), {"--rig", s.rig.string(), "--objects", s.objects.string(), "--shard-frames", "1",
                           "--work", (dir / "work").string(), "--export-out", (dir / "dataset").string(),
                           "--json", "--progress", "none"});
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

std::vector<fs::path> CopySessions(const testing::RelabelSessions& s, const fs::path& to) {
  std::vector<fs::path> out;
  for (const fs::path& session : s.sessions) {
    out.push_back(to / session.filename());
    fs::create_directories(to);
    fs::copy(session, out.back(), fs::copy_options::recursive);
  }
  return out;
}

/// The array job and task of the first task of `step` squeue shows running ("123_1"), or "".
std::string RunningTask(const std::string& step) {
  const pipeline::CommandOutput r = pipeline::RunCommand({"squeue", "-h", "-r", "-o", "%i %T %j"});
  std::istringstream lines(r.out);
  for (std::string id, state, name; lines >> id >> state >> name;)
    if (state == "RUNNING" && name == "mocaplabel-" + step && id.find('_') != std::string::npos) return id;
  return "";
}

TEST(RelabelSlurm, GivesTheLocalRunsAndRedoesOnlyACancelledShard) {
  const testing::RelabelSessions s = testing::MakeRelabelSessions("slurm", {{}, {"funnel"}}, 2);
  const std::vector<fs::path> local = CopySessions(s, s.dir / "local"), cluster = CopySessions(s, s.dir / "cluster");
  std::string out;
  ASSERT_EQ(Mocaplabel(Relabel(local, s.dir / "local", s, {}), &out), 0) << out;

  // Submitted without waiting; one validation shard is cancelled while it runs (one task at a time).
  ASSERT_EQ(Mocaplabel(Relabel(cluster, s.dir / "cluster", s, {"--executor", "slurm", "--no-wait", "--max-running", "1"}), &out), 0) << out;
  std::string cancelled;
  for (int i = 0; i < 600 && cancelled.empty(); ++i) {
    const std::string id = RunningTask("validate");
    if (!id.empty() && id.substr(id.find('_') + 1) == "1") cancelled = id;
    else std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_FALSE(cancelled.empty()) << "validate task 1 never ran";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(pipeline::RunCommand({"scancel", cancelled}).exit_code, 0);

  // relabel --status follows the jobs to their end and reports the cancelled shard with its log.
  const std::string queue = pipeline::RunCommand({"squeue", "-h", "-r", "-o", "%i %T %j"}).out;
  json report;
  int status = -1;
  for (int i = 0; i < 300; ++i) {  // exit 0 while jobs run, 1 once they have ended with a failure
    status = Mocaplabel({"relabel", "--status", "--work", (s.dir / "cluster" / "work").string(), "--json"}, &out);
    report = testing::LastJson(out);
    if (report.value("finished", true)) break;
    EXPECT_EQ(status, 0) << out;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_EQ(status, 1) << out;
  ASSERT_TRUE(report.contains("ok")) << out;
  ASSERT_FALSE(report["ok"].get<bool>()) << out << "\nqueue after scancel:\n" << queue;
  bool reported = false;
  for (const json& f : report["execution"]["failed"])
    if (f["step"] == "validate" && f["task"] == 1) {
      reported = true;
      EXPECT_NE(f["state"].get<std::string>().find("CANCELLED"), std::string::npos) << f.dump();
      EXPECT_TRUE(fs::exists(f["log"].get<std::string>())) << f.dump();
    }
  EXPECT_TRUE(reported) << report["execution"].dump(1);
  EXPECT_FALSE(fs::exists(cluster[0] / "validation" / "validation.json")) << "nothing half-published";

  // The rerun redoes that shard alone, then merges and exports.
  ASSERT_EQ(Mocaplabel(Relabel(cluster, s.dir / "cluster", s, {"--executor", "slurm", "--poll-seconds", "0.2"}), &out), 0) << out;
  report = testing::LastJson(out);
  int label_shards = 0, validate_shards = 0;
  for (const json& r : report["sessions"]) {
    label_shards += r["label"]["run"].get<bool>() ? r["label"]["shards"].get<int>() : 0;
    validate_shards += r["validate"]["shards"].get<int>();
  }
  EXPECT_EQ(label_shards, 0) << out;
  EXPECT_EQ(validate_shards, 1) << out;

  // Byte for byte what the local executor wrote (files carrying times or the command line aside).
  for (size_t i = 0; i < local.size(); ++i)
    for (const char* run : {"labels", "validation"}) {
      const auto a = testing::TreeFiles(local[i] / run), b = testing::TreeFiles(cluster[i] / run);
      EXPECT_FALSE(a.empty()) << local[i] / run;
      EXPECT_TRUE(a == b) << local[i] / run << " differs from " << cluster[i] / run;
    }
  const auto a = testing::TreeFiles(s.dir / "local" / "dataset"), b = testing::TreeFiles(s.dir / "cluster" / "dataset");
  EXPECT_GT(a.size(), 5u);
  EXPECT_EQ(a.size(), b.size());
  for (const auto& [name, bytes] : a) EXPECT_TRUE(b.count(name) && b.at(name) == bytes) << name;
  fs::remove_all(s.dir);
}

TEST(RelabelSlurm, ARefusedOrUnreachableSbatchIsOneClearErrorAndLeavesNothing) {
  const testing::RelabelSessions s = testing::MakeRelabelSessions("slurm_bad", {{"funnel", "oil_bottle"}}, 1);
  std::string out;
  EXPECT_EQ(Mocaplabel(Relabel(s.sessions, s.dir, s, {"--executor", "slurm", "--partition", "nosuch"}), &out), 1) << out;
  EXPECT_NE(out.find("sbatch: refused the label job"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(s.dir / "work" / "slurm" / "jobs.json"));
  EXPECT_FALSE(fs::exists(s.sessions[0] / "labels"));
  EXPECT_TRUE(pipeline::RunCommand({"squeue", "-h", "-n", "mocaplabel-label"}).out.empty()) << "no job left submitted";

  // An extra sbatch argument reaches sbatch as given.
  EXPECT_EQ(Mocaplabel(Relabel(s.sessions, s.dir, s, {"--executor", "slurm", "--sbatch-arg=--time=not-a-time"}), &out), 1) << out;
  EXPECT_NE(out.find("sbatch: refused the label job"), std::string::npos) << out;
  EXPECT_NE(out.find("time"), std::string::npos) << out;

  // A controller that does not answer: a copy of the configuration with another port.
  std::ifstream in(std::getenv("SLURM_CONF"));
  std::stringstream conf;
  conf << in.rdbuf();
  const fs::path dead = s.dir / "dead.conf";
  std::ofstream(dead) << std::regex_replace(conf.str(), std::regex("SlurmctldPort=[0-9]+"), "SlurmctldPort=1");
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(Mocaplabel(Relabel(s.sessions, s.dir, s, {"--executor", "slurm"}), &out, {{"SLURM_CONF", dead.string()}}), 1) << out;
  EXPECT_NE(out.find("sbatch: refused the label job"), std::string::npos) << out;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 120.0);
  EXPECT_FALSE(fs::exists(s.sessions[0] / "labels"));
  fs::remove_all(s.dir);
}

}  // namespace
}  // namespace mocap
