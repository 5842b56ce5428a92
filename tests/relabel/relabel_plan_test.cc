// The relabel plan without rendering: runs' provenance written as the label and validation stages write
// it, then planned against changed inputs. Per-object staleness, the verdict diff, and the planning time
// of 1000 sessions.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>

#include "core/check.h"
#include "pipeline/relabel_plan.h"
#include "pipeline/relabel_tasks.h"
#include "pipeline/run_provenance.h"
#include "session/manifest.h"
#include "tests/pipeline/synthetic_inputs.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// Sets every file's mtime an hour back: out of the 2 s window in which provenance distrusts a fresh
/// file's stat, as a run made earlier than now finds its inputs.
void Age(const fs::path& path) {
  const auto past = fs::file_time_type::clock::now() - std::chrono::hours(1);
  if (fs::is_regular_file(path)) return fs::last_write_time(path, past);
  for (const auto& e : fs::recursive_directory_iterator(path))
    if (e.is_regular_file()) fs::last_write_time(e.path(), past);
}

/// run.json and the finished marker of a label and a validation run of `session`, as the stages write
/// them (run_provenance.h: the same inputs and options, objects_in_session included).
void WriteRuns(const fs::path& session, const fs::path& objects, pipeline::HashCache& cache) {
  const pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(objects);
  Age(session);
  pipeline::RunRecord record{{"mocaplabel", "label"}, {{"objects", objects, false, {}}}, nullptr,
                             pipeline::ObjectsInSession(library, LoadManifest(session))};
  std::vector<pipeline::InputSpec> inputs = {pipeline::SessionInput(session), {"objects", objects, false, {}}};
  for (const pipeline::InputSpec& mesh : pipeline::MeshInputs(pipeline::LabelObjectsOf(library))) inputs.push_back(mesh);
  auto write = [&](const fs::path& dir, const std::string& kind, const json& options, const char* marker) {
    fs::create_directories(dir);
    pipeline::RunProvenance run = pipeline::NewProvenance(kind, record.command, pipeline::RecordedOptions(options, record));
    run.inputs = pipeline::FingerprintInputs(inputs, cache);
    pipeline::WriteRunJson(dir, run);
    std::ofstream(dir / marker) << "{}\n";
    Age(dir);
  };
  write(session / "labels", "label", pipeline::ToJson(LabelOptions{}), "label_manifest.json");
  inputs.insert(inputs.begin() + 1, pipeline::RunFolderInput("labels", session / "labels"));
  write(session / "validation", "validation", pipeline::ToJson(SessionCheckOptions{}), "validation.json");
}
void WriteRuns(const fs::path& session, const fs::path& objects) {
  pipeline::HashCache cache("");
  WriteRuns(session, objects, cache);
}

/// A copy of the session's manifest and streams (what the plan reads; the images are not needed).
fs::path CopySession(const fs::path& from, const fs::path& to) {
  fs::create_directories(to);
  fs::copy_file(from / "manifest.json", to / "manifest.json");
  for (const fs::path& file : SessionStreamFiles(LoadManifest(from))) {
    fs::create_directories((to / file).parent_path());
    fs::copy_file(from / file, to / file, fs::copy_options::overwrite_existing);
  }
  return to;
}

void AddObject(const fs::path& objects, const std::string& name, int id, const std::string& body) {
  pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(objects);
  pipeline::LibraryObject o = library.objects.at(0);
  o.id = id, o.name = name, o.mounts = {{body, Rigid3d()}};
  testing::WriteBoxObj(objects.parent_path() / (name + ".obj"));
  o.mesh = name + ".obj", o.mesh_path = objects.parent_path() / o.mesh;
  library.objects.push_back(o);
  pipeline::WriteObjectLibrary(library, objects);
}

class RelabelPlanTest : public ::testing::Test {
 protected:
  void SetUp() override {
    in_ = testing::MakeInputs("relabel_plan", 2);
    Age(in_.dir);
  }
  void TearDown() override { fs::remove_all(in_.dir); }
  pipeline::RelabelPlan Plan(const std::vector<fs::path>& sessions) {
    pipeline::RelabelPlanOptions options;
    options.objects_file = in_.objects;
    pipeline::HashCache cache("");
    return pipeline::PlanRelabel(sessions, options, cache);
  }
  testing::Inputs in_;
};

TEST_F(RelabelPlanTest, AnotherObjectsEntryOrMeshDoesNotStaleARunItsOwnDoes) {
  AddObject(in_.objects, "other", 7, "elsewhere_body");  // a body the session does not track
  WriteRuns(in_.session, in_.objects);
  EXPECT_FALSE(Plan({in_.session}).sessions[0].label.run);

  // The other object's mount and mesh change: the library file changed, the session's objects did not.
  pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(in_.objects);
  library.objects[1].mounts[0].T_body_mesh = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0.01));
  pipeline::WriteObjectLibrary(library, in_.objects);
  std::ofstream(in_.dir / "other.obj", std::ios::app) << "# edited\n";
  pipeline::RelabelPlan plan = Plan({in_.session});
  EXPECT_FALSE(plan.sessions[0].label.run) << ::testing::PrintToString(plan.sessions[0].label.why);
  EXPECT_FALSE(plan.sessions[0].validate.run);

  // The session's own object: stale from the label stage on, saying which object and why.
  library.objects[0].mounts[0].T_body_mesh = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.002, 0, 0));
  pipeline::WriteObjectLibrary(library, in_.objects);
  plan = Plan({in_.session});
  ASSERT_TRUE(plan.sessions[0].label.run);
  EXPECT_EQ(plan.sessions[0].label.why, std::vector<std::string>{"object box: its objects.yaml entry changed"});
  EXPECT_TRUE(plan.sessions[0].validate.run);
  EXPECT_EQ(plan.sessions[0].validate.why.at(0), "its label run is redone");

  // Its mesh, by content: one byte.
  WriteRuns(in_.session, in_.objects);
  EXPECT_FALSE(Plan({in_.session}).sessions[0].label.run);
  std::ofstream(in_.dir / "box.obj", std::ios::app) << "# one more line\n";
  plan = Plan({in_.session});
  ASSERT_TRUE(plan.sessions[0].label.run);
  EXPECT_NE(plan.sessions[0].label.why.at(0).find("mesh:box"), std::string::npos);
}

TEST_F(RelabelPlanTest, ShardsCoverTheSessionAndThePlanFileRoundTrips) {
  pipeline::RelabelPlanOptions options;
  options.objects_file = in_.objects;
  options.shard_frames = 1;
  pipeline::HashCache cache("");
  const pipeline::RelabelPlan plan = pipeline::PlanRelabel({in_.session}, options, cache);
  const pipeline::SessionPlan& s = plan.sessions.at(0);
  EXPECT_EQ(s.frames, 2);
  EXPECT_EQ(s.label.why, std::vector<std::string>{"no label run yet"});
  ASSERT_EQ(s.label.shards.size(), 2u);
  EXPECT_EQ(s.label.todo, (std::vector<int>{0, 1}));
  EXPECT_EQ(pipeline::StageTasks(plan, pipeline::RelabelStage::kLabel).size(), 2u);
  EXPECT_TRUE(pipeline::StageNeedsMerge(plan, pipeline::RelabelStage::kValidate));
  const json j = pipeline::ToJson(plan);
  EXPECT_EQ(pipeline::ToJson(pipeline::RelabelPlanFromJson(j, "plan.json")), j);
  json bad = j;
  bad["sessions"][0]["label"]["todo"] = {5};
  EXPECT_THROW(pipeline::RelabelPlanFromJson(bad, "plan.json"), InputError);
}

TEST_F(RelabelPlanTest, ThousandSessionsArePlannedInUnderTwoSeconds) {
  std::vector<fs::path> sessions;
  pipeline::HashCache cache("");
  for (int i = 0; i < 1000; ++i) {
    sessions.push_back(CopySession(in_.session, in_.dir / "many" / ("S" + std::to_string(i))));
    WriteRuns(sessions.back(), in_.objects, cache);
  }
  pipeline::RelabelPlan plan = Plan(sessions);  // as a second relabel finds them: all up to date
  for (const pipeline::SessionPlan& s : plan.sessions) ASSERT_FALSE(s.label.run || s.validate.run) << s.session_dir;
  const auto start = std::chrono::steady_clock::now();
  plan = Plan(sessions);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("plan_seconds_1000_sessions", std::to_string(seconds));
  std::printf("planned 1000 sessions in %.3f s (%lld files checked, %lld hashed)\n", seconds,
              static_cast<long long>(plan.files_checked), static_cast<long long>(plan.files_hashed));
  EXPECT_EQ(plan.files_hashed, 0) << "unchanged inputs are recognised by stat alone";
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_LT(seconds, 2.0);
#endif
  // One session's stream changes: that one alone is stale.
  std::ofstream(sessions[500] / "manifest.json", std::ios::app) << " ";
  plan = Plan(sessions);
  int stale = 0;
  for (const pipeline::SessionPlan& s : plan.sessions) stale += s.label.run ? 1 : 0;
  EXPECT_EQ(stale, 1);
  EXPECT_TRUE(plan.sessions[500].label.run);
}

TEST(RelabelVerdicts, ChangesAreCountedPerTransitionAndObject) {
  const std::map<std::string, std::string> before = {{"cam/0/box/1", "accept"}, {"cam/1/box/1", "accept"},
                                                     {"cam/0/cup/2", "reject"}, {"cam/2/cup/2", "suspect"}};
  const std::map<std::string, std::string> after = {{"cam/0/box/1", "reject"}, {"cam/1/box/1", "accept"},
                                                    {"cam/0/cup/2", "accept"}, {"cam/3/cup/2", "accept"}};
  const json changes = pipeline::VerdictChanges(before, after);
  EXPECT_EQ(changes["changed"], 4);
  EXPECT_EQ(changes["unchanged"], 1);
  EXPECT_EQ(changes["transitions"]["accept->reject"], 1);
  EXPECT_EQ(changes["transitions"]["reject->accept"], 1);
  EXPECT_EQ(changes["transitions"]["suspect->none"], 1);
  EXPECT_EQ(changes["transitions"]["none->accept"], 1);
  EXPECT_EQ(changes["objects"]["box"]["accept->reject"], 1);
  EXPECT_EQ(changes["objects"]["cup"].size(), 3u);
}

}  // namespace
}  // namespace mocap
