// `mocaplabel relabel` on this machine, as a user runs it: three simulated sessions labelled, validated
// and exported; nothing redone when nothing changed; after one object's mount changes, only the sessions
// holding that object redone, with the verdict changes reported; bad input refused with one clear line.
#include <gtest/gtest.h>

#include <chrono>
#include <fstream>

#include "pipeline/provenance.h"
#include "tests/relabel/relabel_fixture.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using testing::Mocaplabel;

std::vector<std::string> Args(const testing::RelabelSessions& s, std::vector<std::string> extra) {
  std::vector<std::string> args = {"relabel"};
  for (const fs::path& session : s.sessions) args.push_back(session.string());
  args.insert(args.end(), {"--work", (s.dir / "work").string(), "--export-out", (s.dir / "dataset").string(), "--json",
                           "--progress", "none"});
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

const json& SessionReport(const json& report, const fs::path& session) {
  for (const json& s : report["sessions"])
    if (s["session"] == session.string()) return s;
  static const json none;
  ADD_FAILURE() << "no report for " << session;
  return none;
}

TEST(RelabelCli, RedoesExactlyWhatIsStaleAndReportsTheVerdictChanges) {
  // S1 holds every object, S2 no oil bottle, S3 no funnel.
  const testing::RelabelSessions s = testing::MakeRelabelSessions("local", {{}, {"oil_bottle"}, {"funnel"}}, 2);
  std::string out;
  ASSERT_EQ(Mocaplabel(Args(s, {"--rig", s.rig.string(), "--objects", s.objects.string(), "--shard-frames", "1"}), &out), 0) << out;
  json report = testing::LastJson(out);
  ASSERT_TRUE(report["ok"].get<bool>()) << out;
  for (const fs::path& session : s.sessions) {
    EXPECT_TRUE(SessionReport(report, session)["label"]["run"].get<bool>()) << session;
    EXPECT_TRUE(fs::exists(session / "labels" / "label_manifest.json"));
    EXPECT_TRUE(fs::exists(session / "validation" / "validation.json"));
    EXPECT_FALSE(fs::exists(session / "labels.shards")) << "merged shards leave no folder";
    EXPECT_TRUE(pipeline::ReadRunJson(session / "labels").shard.is_null());
  }
  EXPECT_TRUE(fs::exists(s.dir / "dataset" / "export.json"));
  EXPECT_FALSE(report["export"]["up_to_date"].get<bool>());

  // Nothing changed: no work, decided quickly (the rig and library are the ones the runs recorded).
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(Mocaplabel(Args(s, {}), &out), 0) << out;
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report = testing::LastJson(out);
  EXPECT_TRUE(report["execution"]["steps"].empty()) << out;
  EXPECT_LT(report["planning_seconds"].get<double>(), 1.0);
  EXPECT_TRUE(report["export"]["up_to_date"].get<bool>()) << out;
  EXPECT_LT(wall_s, 5.0) << "a no-op relabel, process start and export check included";
  for (const fs::path& session : s.sessions) EXPECT_FALSE(SessionReport(report, session)["label"]["run"].get<bool>());

  // The oil bottle's mount moves by 4 cm: S1 and S3 are redone from the label stage on, S2 (which has no
  // oil bottle) is not.
  const auto s2_labels_before = testing::TreeFiles(s.sessions[1] / "labels");
  testing::ShiftMount(s.objects, "oil_bottle", 0.04);
  ASSERT_EQ(Mocaplabel(Args(s, {"--dry-run"}), &out), 0) << out;
  const json plan = testing::LastJson(out)["plan"];
  EXPECT_TRUE(plan["sessions"][0]["label"]["run"].get<bool>());
  EXPECT_EQ(plan["sessions"][0]["label"]["why"][0], "object oil_bottle: its objects.yaml entry changed");
  EXPECT_FALSE(plan["sessions"][1]["label"]["run"].get<bool>()) << plan.dump(1);
  EXPECT_FALSE(plan["sessions"][1]["validate"]["run"].get<bool>());

  ASSERT_EQ(Mocaplabel(Args(s, {}), &out), 0) << out;
  report = testing::LastJson(out);
  for (int i : {0, 2}) {
    const json& r = SessionReport(report, s.sessions[static_cast<size_t>(i)]);
    EXPECT_TRUE(r["label"]["run"].get<bool>() && r["validate"]["run"].get<bool>()) << r.dump(1);
    const json& changes = r["verdict_changes"];
    EXPECT_GT(changes["changed"].get<int>(), 0) << changes.dump(1);
    EXPECT_TRUE(changes["objects"].contains("oil_bottle")) << changes.dump(1);
    int to_worse = 0;
    for (const auto& [what, n] : changes["objects"]["oil_bottle"].items())
      if (what == "accept->reject" || what == "accept->suspect" || what == "suspect->reject") to_worse += n.get<int>();
    EXPECT_GT(to_worse, 0) << changes.dump(1);
  }
  EXPECT_FALSE(SessionReport(report, s.sessions[1])["label"]["run"].get<bool>());
  EXPECT_EQ(testing::TreeFiles(s.sessions[1] / "labels"), s2_labels_before);
  EXPECT_FALSE(report["export"]["up_to_date"].get<bool>()) << "the dataset follows the new labels";

  // Mounting it back restores the verdicts.
  testing::ShiftMount(s.objects, "oil_bottle", -0.04);
  ASSERT_EQ(Mocaplabel(Args(s, {"--stages", "label,validate"}), &out), 0) << out;
  report = testing::LastJson(out);
  const json& back = SessionReport(report, s.sessions[0])["verdict_changes"];
  EXPECT_GT(back["changed"].get<int>(), 0) << back.dump(1);
  fs::remove_all(s.dir);
}

TEST(RelabelCli, BadInputIsOneClearLineAndChangesNothing) {
  const testing::RelabelSessions s = testing::MakeRelabelSessions("bad", {{"funnel", "oil_bottle"}}, 1);
  std::string out;
  ASSERT_EQ(Mocaplabel({"relabel", s.sessions[0].string(), "--rig", s.rig.string(), "--objects", s.objects.string(),
                        "--stages", "label", "--work", (s.dir / "work").string(), "--progress", "none"}, &out), 0) << out;
  const auto labels = testing::TreeFiles(s.sessions[0] / "labels");
  auto expect_error = [&](const std::vector<std::string>& args, const std::string& needle) {
    std::vector<std::string> argv = {"relabel"};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.end(), {"--work", (s.dir / "work").string(), "--progress", "none"});
    EXPECT_EQ(Mocaplabel(argv, &out), 1) << out;
    EXPECT_NE(out.find(needle), std::string::npos) << out;
  };
  // A session that is not there.
  expect_error({(s.dir / "nowhere").string()}, "nowhere: no such session (moved or removed?)");
  // A session moved: its runs name the old folder.
  const fs::path moved = s.dir / "moved";
  fs::rename(s.sessions[0], moved);
  expect_error({moved.string()}, "the session was moved or copied; pass --relabel-moved");
  fs::rename(moved, s.sessions[0]);
  // A run from a newer mocaplabel.
  const fs::path run_json = s.sessions[0] / "labels" / "run.json";
  const std::string original = [&] { std::ifstream in(run_json); std::stringstream t; t << in.rdbuf(); return t.str(); }();
  json run = json::parse(original);
  run["tool_version"] = "99.0.0";
  std::ofstream(run_json) << run.dump(2);
  expect_error({s.sessions[0].string()}, "made by mocaplabel 99.0.0, newer than this one");
  // A run without provenance.
  fs::remove(run_json);
  expect_error({s.sessions[0].string()}, "run.json: missing: the run has no provenance");
  std::ofstream(run_json) << original;
  // Flags that do not fit.
  expect_error({s.sessions[0].string(), "--stages", "export"}, "the export stage needs --export-out");
  expect_error({"--status"}, "jobs.json: missing: no Slurm jobs were submitted");
  EXPECT_EQ(testing::TreeFiles(s.sessions[0] / "labels"), labels) << "nothing was touched";
  fs::remove_all(s.dir);
}

}  // namespace
}  // namespace mocap
