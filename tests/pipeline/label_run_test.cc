// Label runs as the pipeline writes them: shards that merge into the run one pass writes (byte for
// byte), run.json in every run and staleness from it (one changed byte of a mesh, the rig or a session
// stream makes a run stale; touching a file does not), and the typed record's round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/check.h"
#include "pipeline/label_run.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/provenance.h"
#include "pipeline/rig.h"
#include "pipeline/shards.h"
#include "pipeline/validate_stage.h"
#include "tests/pipeline/synthetic_inputs.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

std::string ReadBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

pipeline::LabelRunRequest Request(const testing::Inputs& in, const fs::path& out) {
  pipeline::LabelRunRequest request;
  request.session_dir = in.session, request.rig_file = in.rig, request.objects_file = in.objects, request.out_dir = out;
  request.label.threads = 2;
  request.label.output.write_bop_masks = true;
  request.command = {"mocaplabel", "label"};
  return request;
}

/// Every file under `dir` but run.json and label_manifest.json (which carry times), relative path -> bytes.
std::map<std::string, std::string> RunFiles(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name != "run.json" && name != "label_manifest.json")
      files[fs::relative(e.path(), dir).string()] = ReadBytes(e.path());
  }
  return files;
}

TEST(LabelRun, ThreeShardsMergeIntoTheRunOnePassWrites) {
  const testing::Inputs in = testing::MakeInputs("shards", 10);
  pipeline::RunLabel(Request(in, in.dir / "one"));
  std::vector<fs::path> shard_dirs;
  for (const pipeline::Shard& shard : pipeline::SplitShards(10, 3)) {
    pipeline::LabelRunRequest request = Request(in, pipeline::ShardDir(in.dir / "sharded", shard));
    request.shard = shard;
    pipeline::RunLabel(request);
    EXPECT_EQ(pipeline::ReadRunJson(request.out_dir).shard["count"], 3);
    shard_dirs.push_back(request.out_dir);
  }
  pipeline::MergeLabelShards(shard_dirs, in.dir / "sharded");
  const auto one = RunFiles(in.dir / "one"), merged = RunFiles(in.dir / "sharded");
  EXPECT_EQ(ReadBytes(in.dir / "one" / "labels.jsonl"), ReadBytes(in.dir / "sharded" / "labels.jsonl"));
  ASSERT_EQ(one.size(), merged.size());
  EXPECT_GT(one.size(), 10u * 4);  // instance, class, depth, mask bits and BOP masks of 10 frames
  for (const auto& [name, bytes] : one) {
    ASSERT_TRUE(merged.count(name)) << name;
    EXPECT_EQ(merged.at(name), bytes) << name;
  }
  const auto manifest = nlohmann::json::parse(ReadBytes(in.dir / "sharded" / "label_manifest.json"));
  EXPECT_EQ(manifest["frames"], 10);
  EXPECT_TRUE(pipeline::ReadRunJson(in.dir / "sharded").shard.is_null());
  EXPECT_FALSE(fs::exists(in.dir / "sharded.shards"));
  EXPECT_GT(pipeline::LabelRun::Read(in.dir / "sharded").records.size(), 0u);
}

TEST(ValidationRun, TwoShardsMergeIntoTheRunOnePassWrites) {
  const testing::Inputs in = testing::MakeInputs("validation_shards", 6);
  pipeline::RunLabel(Request(in, in.dir / "L"));
  pipeline::ValidateRunRequest request;
  request.session_dir = in.session, request.labels_dir = in.dir / "L", request.objects_file = in.objects;
  request.check.threads = 2;
  // The shards below begin at frame 3: with cross-checks at multiples of 3 they restart the trackers
  // where the one pass does (tracking.reacquire_every, docs/validation.md).
  request.check.validate.tracking.reacquire_every = 3;
  request.out_dir = in.dir / "V";
  pipeline::RunValidate(request);
  std::vector<fs::path> shard_dirs;
  for (const pipeline::Shard& shard : pipeline::SplitShards(6, 2)) {
    pipeline::ValidateRunRequest part = request;
    part.shard = shard;
    part.out_dir = pipeline::ShardDir(in.dir / "V2", shard);
    EXPECT_EQ(pipeline::RunValidate(part).records.size(), 3u) << "shard " << shard.index;
    shard_dirs.push_back(part.out_dir);
  }
  pipeline::MergeValidationShards(shard_dirs, in.dir / "V2");
  const std::string one = ReadBytes(in.dir / "V" / "validation.jsonl");
  EXPECT_GT(std::count(one.begin(), one.end(), '\n'), 0);
  EXPECT_EQ(ReadBytes(in.dir / "V2" / "validation.jsonl"), one);
  const auto a = nlohmann::json::parse(ReadBytes(in.dir / "V" / "validation.json"));
  const auto b = nlohmann::json::parse(ReadBytes(in.dir / "V2" / "validation.json"));
  for (const char* key : {"records", "records_checked", "verdicts", "reasons", "position_error_mm", "labels", "session"})
    EXPECT_EQ(a[key], b[key]) << key;
}

TEST(LabelRun, ShardsThatDoNotTileAreRefused) {
  const testing::Inputs in = testing::MakeInputs("shards_gap", 6);
  const std::vector<pipeline::Shard> shards = pipeline::SplitShards(6, 3);
  std::vector<fs::path> dirs;
  for (size_t k : {0u, 2u}) {  // the middle shard is missing
    pipeline::LabelRunRequest request = Request(in, pipeline::ShardDir(in.dir / "L", shards[k]));
    request.shard = shards[k];
    pipeline::RunLabel(request);
    dirs.push_back(request.out_dir);
  }
  EXPECT_THROW(pipeline::MergeLabelShards(dirs, in.dir / "L"), InputError);
  EXPECT_FALSE(fs::exists(in.dir / "L"));
}

/// Changes one byte of `file` in place (same size).
void FlipOneByte(const fs::path& file, size_t offset) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(offset));
  char c = 0;
  f.get(c);
  f.seekp(static_cast<std::streamoff>(offset));
  f.put(c == ' ' ? '\t' : static_cast<char>(c ^ 1));
}

void AgeFiles(const fs::path& dir) {  // out of the 2 s window in which a rewrite could keep its mtime
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) fs::last_write_time(e.path(), fs::file_time_type::clock::now() - std::chrono::hours(1));
}

pipeline::StaleReport Stale(const fs::path& run) {
  pipeline::HashCache cache("");
  return pipeline::CheckStale(pipeline::ReadRunJson(run), {}, cache);
}

TEST(LabelRun, RunJsonRecordsEveryInputAndTellsWhenItIsStale) {
  const testing::Inputs in = testing::MakeInputs("stale", 3);
  AgeFiles(in.dir);
  pipeline::RunLabel(Request(in, in.dir / "L"));
  const pipeline::RunProvenance run = pipeline::ReadRunJson(in.dir / "L");
  std::set<std::string> roles;
  for (const auto& input : run.inputs) roles.insert(input.role);
  EXPECT_EQ(roles, (std::set<std::string>{"session", "rig", "objects", "mesh:box"}));
  EXPECT_EQ(run.kind, "label");
  EXPECT_FALSE(Stale(in.dir / "L").stale);
  // Touching without changing a byte: not stale.
  for (const fs::path& file : {in.rig, in.dir / "box.obj", in.session / "trackers/ndi/samples.jsonl"})
    fs::last_write_time(file, fs::file_time_type::clock::now());
  EXPECT_FALSE(Stale(in.dir / "L").stale);
  // One byte of each kind of input: stale, naming it.
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {in.dir / "box.obj", "mesh:box"}, {in.rig, "rig"}, {in.session / "trackers/ndi/samples.jsonl", "session"}};
  for (const auto& [file, role] : cases) {
    const std::string before = ReadBytes(file);
    FlipOneByte(file, before.size() / 2);
    const pipeline::StaleReport stale = Stale(in.dir / "L");
    ASSERT_TRUE(stale.stale) << role;
    ASSERT_EQ(stale.changes.size(), 1u) << role;
    EXPECT_EQ(stale.changes[0].role, role);
    std::ofstream(file, std::ios::binary | std::ios::trunc) << before;
    EXPECT_FALSE(Stale(in.dir / "L").stale) << role << " restored";
  }
}

TEST(LabelRun, RecordsRoundTripThroughTheirOneReaderAndWriter) {
  const testing::Inputs in = testing::MakeInputs("records", 2);
  pipeline::RunLabel(Request(in, in.dir / "L"));
  std::ifstream file(in.dir / "L" / "labels.jsonl");
  int lines = 0;
  for (std::string line; std::getline(file, line); ++lines)
    EXPECT_EQ(pipeline::ToJson(pipeline::LabelRecordFromJson(nlohmann::json::parse(line), "labels.jsonl")).dump(), line);
  EXPECT_EQ(lines, 2);
  // With measured depth the visible mask's split into measured and assumed pixels is written.
  const pipeline::LabelRecord first = pipeline::LabelRecordFromJson(
      nlohmann::json::parse(ReadBytes(in.dir / "L" / "labels.jsonl").substr(0, ReadBytes(in.dir / "L" / "labels.jsonl").find('\n'))),
      "labels.jsonl:1");
  ASSERT_TRUE(first.has_pose && first.px_count_valid);
  ASSERT_TRUE(first.px_count_visib_measured && first.px_count_visib_assumed && first.mask_confidence);
  EXPECT_EQ(*first.px_count_visib_measured + *first.px_count_visib_assumed, first.px_count_visib);
  EXPECT_GE(*first.mask_confidence, 0.0);
  EXPECT_LE(*first.mask_confidence, 1.0);
  // A label run written before those fields still reads.
  nlohmann::json older = pipeline::ToJson(first);
  for (const char* key : {"px_count_visib_measured", "px_count_visib_assumed", "mask_confidence"}) older.erase(key);
  EXPECT_FALSE(pipeline::LabelRecordFromJson(older, "labels.jsonl:1").mask_confidence);
  nlohmann::json bad = nlohmann::json::parse(ReadBytes(in.dir / "L" / "labels.jsonl").substr(0, ReadBytes(in.dir / "L" / "labels.jsonl").find('\n')));
  bad.erase("instance");
  EXPECT_THROW(pipeline::LabelRecordFromJson(bad, "labels.jsonl:1"), InputError);
  // An existing folder that is not a label run is never replaced.
  fs::create_directories(in.dir / "precious");
  std::ofstream(in.dir / "precious" / "notes.txt") << "keep";
  EXPECT_THROW(pipeline::RunLabel(Request(in, in.dir / "precious")), InputError);
  EXPECT_TRUE(fs::exists(in.dir / "precious" / "notes.txt"));
}

TEST(LabelRun, ARigCameraTheSessionDoesNotHaveIsAnError) {
  // A misspelt camera would otherwise be dropped and the recorded calibration used.
  const testing::Inputs in = testing::MakeInputs("rig_camera", 1);
  pipeline::Rig rig = pipeline::ReadRig(in.rig);
  rig.cameras[0].name = "cam9";
  pipeline::WriteRig(rig, in.dir / "typo.yaml");
  pipeline::LabelRunRequest request = Request(in, in.dir / "L");
  request.rig_file = in.dir / "typo.yaml";
  try {
    pipeline::RunLabel(request);
    FAIL() << "a rig camera not in the session was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("typo.yaml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'cam9'"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(in.dir / "L"));
}

}  // namespace
}  // namespace mocap
