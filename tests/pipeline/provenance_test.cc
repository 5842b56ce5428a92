#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <fstream>

#include "core/check.h"
#include "pipeline/build_info.h"
#include "pipeline/content_hash.h"
#include "pipeline/hash_cache.h"
#include "pipeline/provenance.h"
#include "pipeline/run_provenance.h"

namespace mocap::pipeline {
namespace {
namespace fs = std::filesystem;

// Each test gets its own empty folder; the hash cache lives in it too (never the user's cache).
class ProvenanceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::path(::testing::TempDir()) /
            ("mocap_provenance_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    cache_dir_ = root_ / "cache";
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path Write(const std::string& relative, const std::string& bytes) {
    const fs::path file = root_ / relative;
    fs::create_directories(file.parent_path());
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    return file;
  }
  // Inputs exist for a while before a run in practice; a file modified within the racy window is
  // always hashed (content_hash.h), which these tests of the stat fast path must avoid.
  static void SetAge(const fs::path& file, std::chrono::seconds age) {
    fs::last_write_time(file, fs::file_time_type::clock::now() - age);
  }
  void AgeAll() {
    for (const auto& entry : fs::recursive_directory_iterator(root_)) {
      if (entry.is_regular_file()) SetAge(entry.path(), std::chrono::hours(1));
    }
  }
  // Rewrites one byte in place; the size stays, the mtime moves to now.
  static void FlipByte(const fs::path& file, size_t offset) {
    std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
    io.seekg(static_cast<std::streamoff>(offset));
    const char old = static_cast<char>(io.get());
    io.seekp(static_cast<std::streamoff>(offset));
    io.put(static_cast<char>(old ^ 0x01));
  }
  // A run with a file input "rig" and a tree input "session" (two members of three entries).
  RunProvenance MakeRun(HashCache& cache) {
    Write("rig.yaml", "camera: kinect2\n");
    Write("session/manifest.json", "{\"frames\": 3}\n");
    Write("session/cameras/k0/000000.png", std::string(5000, 'a'));
    Write("session/cameras/k0/000001.png", std::string(5000, 'b'));
    Write("session/scratch.txt", "not a member\n");
    AgeAll();
    RunProvenance run = NewProvenance("label", {"mocaplabel", "label"}, {{"frames", 3}});
    run.inputs = FingerprintInputs({{"rig", root_ / "rig.yaml", false, {}},
                                    {"session", root_ / "session", true, {"manifest.json", "cameras"}}},
                                   cache);
    return run;
  }

  fs::path root_, cache_dir_;
};

TEST_F(ProvenanceTest, TreeDigestIgnoresOrderAndSeesOneByte) {
  const std::string digest = TreeDigest({{"a/x", HashBytesXxh3("1")}, {"b", HashBytesXxh3("2")}});
  EXPECT_EQ(digest, TreeDigest({{"b", HashBytesXxh3("2")}, {"a/x", HashBytesXxh3("1")}}));
  EXPECT_NE(digest, TreeDigest({{"a/x", HashBytesXxh3("1")}, {"b", HashBytesXxh3("3")}}));

  HashCache cache(cache_dir_);
  Write("t/one.bin", std::string(3000, 'x'));
  Write("t/sub/two.bin", std::string(3000, 'y'));
  const InputRecord before = FingerprintInputs({{"t", root_ / "t", true, {}}}, cache).at(0);
  EXPECT_EQ(before.files, 2);
  EXPECT_EQ(before.size_bytes, 6000u);
  FlipByte(root_ / "t/sub/two.bin", 1234);
  const InputRecord after = FingerprintInputs({{"t", root_ / "t", true, {}}}, cache).at(0);
  EXPECT_NE(before.hash, after.hash);
}

TEST_F(ProvenanceTest, RunJsonRoundTrip) {
  HashCache cache(cache_dir_);
  RunProvenance run = MakeRun(cache);
  run.shard = {{"index", 1}, {"count", 4}, {"begin", 100}, {"end", 200}};
  WriteRunJson(root_ / "run", run);
  const RunProvenance back = ReadRunJson(root_ / "run");
  EXPECT_EQ(ToJson(back), ToJson(run));
  EXPECT_EQ(back.kind, "label");
  EXPECT_EQ(back.tool_version, CurrentBuildInfo().version);
  ASSERT_EQ(back.inputs.size(), 2u);
  EXPECT_EQ(back.inputs[1].files, 3);  // manifest + two frames; scratch.txt is not a member
  EXPECT_EQ(back.created_utc.size(), 20u);
  EXPECT_FALSE(fs::exists(root_ / "run" / (".run.json.tmp." + std::to_string(::getpid()))));
}

// The InputError message of parsing `json`, "" when it parses.
std::string FromJsonError(const nlohmann::json& json) {
  try {
    ProvenanceFromJson(json, "run.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(ProvenanceTest, RunJsonIsStrict) {
  HashCache cache(cache_dir_);
  const nlohmann::json good = ToJson(MakeRun(cache));
  EXPECT_EQ(FromJsonError(good), "");

  nlohmann::json misspelt = good;
  misspelt["tool_versoin"] = misspelt["tool_version"];
  misspelt.erase("tool_version");
  EXPECT_NE(FromJsonError(misspelt).find("'tool_versoin'"), std::string::npos) << FromJsonError(misspelt);
  misspelt.erase("tool_versoin");
  EXPECT_NE(FromJsonError(misspelt).find("'tool_version' is missing"), std::string::npos);

  nlohmann::json mistyped = good;
  mistyped["inputs"][1]["size_bytes"] = "12";
  EXPECT_NE(FromJsonError(mistyped).find("'inputs[1].size_bytes' must be"), std::string::npos)
      << FromJsonError(mistyped);

  nlohmann::json no_hash = good;
  no_hash["inputs"][0].erase("hash");
  EXPECT_NE(FromJsonError(no_hash).find("'inputs[0].hash' is missing"), std::string::npos);

  nlohmann::json bad_shard = good;
  bad_shard["shard"] = {{"index", 0}, {"count", 2}, {"begin", 0}};
  EXPECT_NE(FromJsonError(bad_shard).find("'shard.end' is missing"), std::string::npos);

  nlohmann::json newer = good;
  newer["format_version"] = kRunJsonFormatVersion + 1;
  EXPECT_NE(FromJsonError(newer).find("newer"), std::string::npos);

  EXPECT_THROW(ReadRunJson(root_ / "not_a_run"), InputError);
  Write("broken/run.json", "{\"kind\": ");
  try {
    ReadRunJson(root_ / "broken");
    FAIL() << "malformed run.json accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), (root_ / "broken" / "run.json").string());
  }
}

TEST_F(ProvenanceTest, MissingInputNamesItsRole) {
  HashCache cache(cache_dir_);
  try {
    FingerprintInputs({{"mesh:mug", root_ / "mug.ply", false, {}}}, cache);
    FAIL() << "missing input accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh:mug input"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mug.ply"), std::string::npos) << e.what();
  }
  Write("session/manifest.json", "{}");
  EXPECT_THROW(FingerprintInputs({{"session", root_ / "session", true, {"manifest.json", "cameras"}}}, cache),
               InputError);
}

TEST_F(ProvenanceTest, UnchangedRunIsNotStaleAndReadsNothing) {
  HashCache cache(cache_dir_);
  const RunProvenance run = MakeRun(cache);
  const StaleReport report = CheckStale(run, {}, cache);
  EXPECT_FALSE(report.stale) << ToJson(report).dump();
  EXPECT_EQ(report.files_checked, 4);
  EXPECT_EQ(report.files_hashed, 0);
  // A fresh cache (another machine, a cleared cache) changes nothing: the stat fast path is in run.json.
  HashCache empty_cache(fs::path{});
  EXPECT_EQ(CheckStale(run, {}, empty_cache).files_hashed, 0);
}

TEST_F(ProvenanceTest, TouchWithoutChangeIsNotStaleAndCachedAfterwards) {
  RunProvenance run;
  {
    HashCache cache(cache_dir_);
    run = MakeRun(cache);
  }
  SetAge(root_ / "rig.yaml", std::chrono::minutes(30));
  SetAge(root_ / "session/cameras/k0/000001.png", std::chrono::minutes(30));
  {
    HashCache cache(cache_dir_);  // a later process: the cache comes from disk
    const StaleReport first = CheckStale(run, {}, cache);
    EXPECT_FALSE(first.stale) << ToJson(first).dump();
    EXPECT_EQ(first.files_hashed, 2);  // the touched file and the touched frame
  }
  HashCache cache(cache_dir_);
  const StaleReport second = CheckStale(run, {}, cache);
  EXPECT_FALSE(second.stale);
  EXPECT_EQ(second.files_hashed, 0);
  EXPECT_TRUE(fs::exists(HashCacheFile(cache_dir_)));
}

TEST_F(ProvenanceTest, OneByteChangedMakesTheRunStale) {
  HashCache cache(cache_dir_);
  const RunProvenance run = MakeRun(cache);
  FlipByte(root_ / "rig.yaml", 3);
  const StaleReport report = CheckStale(run, {}, cache);
  EXPECT_TRUE(report.stale);
  ASSERT_EQ(report.changes.size(), 1u);
  EXPECT_EQ(report.changes[0].role, "rig");
  EXPECT_EQ(report.changes[0].what, "content changed");
}

TEST_F(ProvenanceTest, OneByteChangedInATreeMakesTheRunStale) {
  HashCache cache(cache_dir_);
  const RunProvenance run = MakeRun(cache);
  FlipByte(root_ / "session/cameras/k0/000000.png", 4999);
  const StaleReport report = CheckStale(run, {}, cache);
  ASSERT_EQ(report.changes.size(), 1u);
  EXPECT_EQ(report.changes[0].role, "session");
  EXPECT_EQ(report.changes[0].what, "content changed");
  // A file outside the tree's members changes nothing.
  const RunProvenance run2 = MakeRun(cache);
  Write("session/scratch.txt", "changed\n");
  EXPECT_FALSE(CheckStale(run2, {}, cache).stale);
}

TEST_F(ProvenanceTest, RemovedInputIsMissing) {
  HashCache cache(cache_dir_);
  const RunProvenance run = MakeRun(cache);
  fs::remove(root_ / "rig.yaml");
  fs::remove(root_ / "session/manifest.json");
  const StaleReport report = CheckStale(run, {}, cache);
  ASSERT_EQ(report.changes.size(), 2u);
  EXPECT_EQ(report.changes[0].role, "rig");
  EXPECT_EQ(report.changes[0].what, "missing");
  EXPECT_EQ(report.changes[1].role, "session");
  EXPECT_NE(report.changes[1].what.find("missing"), std::string::npos) << report.changes[1].what;
}

TEST_F(ProvenanceTest, OverridesCompareTheGivenFile) {
  HashCache cache(cache_dir_);
  const RunProvenance run = MakeRun(cache);
  const fs::path same = Write("copy_of_rig.yaml", "camera: kinect2\n");
  const fs::path other = Write("new_rig.yaml", "camera: kinect1\n");
  EXPECT_FALSE(CheckStale(run, {{"rig", same}}, cache).stale);

  const StaleReport changed = CheckStale(run, {{"rig", other}}, cache);
  ASSERT_EQ(changed.changes.size(), 1u);
  EXPECT_EQ(changed.changes[0].what, "different file given (content changed)");
  EXPECT_EQ(changed.changes[0].path, other.string());

  const StaleReport unknown = CheckStale(run, {{"objects", same}}, cache);
  ASSERT_EQ(unknown.changes.size(), 1u);
  EXPECT_EQ(unknown.changes[0].role, "objects");
  EXPECT_EQ(unknown.changes[0].what, "not recorded in the run");
}

}  // namespace
}  // namespace mocap::pipeline

namespace mocap::pipeline {
namespace {

// run.json's label options: the visible-mask rule and the colour test on depth holes round-trip, and a
// run written before either was recorded reads as what made it (BOP19's rule, no colour test), so a
// relabel under today's defaults finds it stale.
TEST(LabelRunOptions, VisibilityRuleAndHoleColourRoundTripAndOldRunsReadAsMadeWithout) {
  LabelOptions options;
  options.visibility.rule = VisibilityRule::kCombined;
  options.visibility.hole_colour = false;
  nlohmann::json json = ToJson(options);
  LabelOptions back = LabelOptionsFromJson(json, "run.json");
  EXPECT_EQ(back.visibility.rule, VisibilityRule::kCombined);
  EXPECT_FALSE(back.visibility.hole_colour);
  options.visibility.hole_colour = true;
  EXPECT_TRUE(LabelOptionsFromJson(ToJson(options), "run.json").visibility.hole_colour);
  json = ToJson(options);
  json["visibility"].erase("rule");
  json["visibility"].erase("hole_colour");
  back = LabelOptionsFromJson(json, "run.json");
  EXPECT_EQ(back.visibility.rule, VisibilityRule::kBop19);
  EXPECT_FALSE(back.visibility.hole_colour);
  EXPECT_NE(ToJson(back), ToJson(LabelOptions{})) << "an old run differs from today's defaults";
}

}  // namespace
}  // namespace mocap::pipeline
