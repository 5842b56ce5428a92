// Filters and splits on datasets built in memory (counts as docs/export.md says), and the export's bad
// inputs: a label run of another session, an object id clash, an output folder holding something else,
// an unchanged re-export.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "core/check.h"
#include "exporters/export/export.h"
#include "pipeline/object_library.h"
#include "tests/exporters/bop/export_fixture.h"
#include "tests/session/full_disk.h"

namespace mocap {
namespace {
namespace fs = std::filesystem;
using namespace exporters;

/// `frames` frames at 30 Hz in each of `scenes` scenes (sessions), two instances each, all accepted.
Dataset MakeDataset(int scenes, int frames) {
  Dataset d;
  for (int s = 0; s < scenes; ++s) {
    ExportScene scene;
    scene.scene_id = s + 1, scene.session_dir = "/sessions/" + std::to_string(s), scene.camera = "cam";
    d.scenes.push_back(scene);
    for (int i = 0; i < frames; ++i) {
      ExportFrame f;
      f.scene = static_cast<size_t>(s), f.index = i, f.stamp_ns = 1'000'000'000LL + i * 33'333'333LL;
      f.T_tracker_camera = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.001 * i, 0, 0));  // 1 mm per frame
      for (int k = 1; k <= 2; ++k) {
        ExportInstance in;
        in.record.instance = k, in.record.object = k, in.record.has_pose = true;
        in.record.px_count_visib = 100, in.record.visib_fract = 0.5;
        in.record.t_m = Eigen::Vector3d(0, 0, 1);
        in.has_check = true, in.verdict = "accept";
        f.instances.push_back(in);
      }
      d.frames.push_back(f);
    }
  }
  return d;
}

ExportSplitOptions NoSplit() {
  ExportSplitOptions o;
  o.by = SplitBy::kNone;
  return o;
}

TEST(ExportSelection, VerdictAndFlagFiltersDropTheFrameOfAVisibleBadLabel) {
  Dataset d = MakeDataset(1, 10);
  d.frames[2].instances[0].verdict = "reject";
  d.frames[3].instances[1].record.flags = {"gap"};
  d.frames[4].instances[1].record.flags = {"outside_image"}, d.frames[4].instances[1].record.px_count_visib = 0;
  d.frames[5].instances[0].has_check = false;  // unchecked: kept by default
  d.frames[6].instances[0].record.visib_fract = 0.05;
  ExportFilterOptions f;
  f.min_visib_fract = 0.1;
  const SelectionSummary s = SelectFrames(d, f, NoSplit());
  EXPECT_EQ(s.frames_in, 10);
  EXPECT_EQ(s.frames_kept, 8);
  EXPECT_EQ(s.frames_removed.at("a label left out: verdict reject"), 1);
  EXPECT_EQ(s.frames_removed.at("a label left out: flag gap"), 1);
  EXPECT_EQ(s.instances_removed.at("flag outside_image"), 1);  // shows nothing: only the label goes
  EXPECT_EQ(s.instances_removed.at("visib_fract < 0.1"), 1);
  EXPECT_EQ(s.instances_kept, 8 * 2 - 2);
  EXPECT_EQ(s.frames_per_split.at("train"), 8);
}

TEST(ExportSelection, MinimumMotionAndEveryNthThinNearDuplicates) {
  Dataset d = MakeDataset(1, 30);
  ExportFilterOptions f;
  f.min_motion_mm = 4.5;  // the camera moves 1 mm per frame: every 5th frame
  SelectionSummary s = SelectFrames(d, f, NoSplit());
  EXPECT_EQ(s.frames_kept, 6);
  EXPECT_EQ(s.frames_removed.at("min motion"), 24);
  Dataset e = MakeDataset(1, 30);
  ExportFilterOptions every;
  every.every_nth = 4;
  s = SelectFrames(e, every, NoSplit());
  EXPECT_EQ(s.frames_kept, 8);  // frames 0, 4, ..., 28
  EXPECT_EQ(e.frames[1].im_id, 4) << "im_id is the frame's index, whatever was left out";
}

TEST(ExportSelection, TimeSplitsKeepTheGuardGapAndAreDeterministic) {
  for (uint64_t seed : {1, 2, 3, 4, 5}) {
    Dataset d = MakeDataset(2, 900);  // 30 s per scene
    ExportSplitOptions o;
    o.block_s = 3, o.guard_s = 0.5, o.seed = seed;
    const SelectionSummary s = SelectFrames(d, {}, o);
    EXPECT_GT(s.frames_per_split.at("train"), 0);
    EXPECT_GT(s.frames_removed.at("guard gap"), 0);
    for (const ExportFrame& a : d.frames) {
      for (const ExportFrame& b : d.frames) {
        if (a.scene == b.scene && a.split != b.split) {
          ASSERT_GE(std::llabs(a.stamp_ns - b.stamp_ns), 500'000'000LL) << "seed " << seed;
        }
      }
    }
    Dataset again = MakeDataset(2, 900);
    SelectFrames(again, {}, o);
    ASSERT_EQ(again.frames.size(), d.frames.size());
    for (size_t i = 0; i < d.frames.size(); ++i) EXPECT_EQ(again.frames[i].split, d.frames[i].split);
  }
}

TEST(ExportSelection, SessionSplitsKeepEachSessionWhole) {
  Dataset d = MakeDataset(10, 20);
  ExportSplitOptions o;
  o.by = SplitBy::kSession;
  const SelectionSummary s = SelectFrames(d, {}, o);
  std::map<size_t, std::set<std::string>> splits_of_scene;
  for (const ExportFrame& f : d.frames) splits_of_scene[f.scene].insert(f.split);
  for (const auto& [scene, splits] : splits_of_scene) EXPECT_EQ(splits.size(), 1u);
  EXPECT_EQ(s.frames_per_split.at("train"), 160);
  EXPECT_EQ(s.frames_per_split.at("val"), 20);
  EXPECT_EQ(s.frames_per_split.at("test"), 20);
}

TEST(ExportErrors, MismatchedRunsClashingIdsAndForeignFoldersAreOneClearError) {
  const testing::LabelledSession a = testing::MakeLabelledSession("err_a", 4), b = testing::MakeLabelledSession("err_b", 4);
  std::string output;
  const fs::path out = a.dir / "D";
  // b's label run given for session a.
  EXPECT_EQ(testing::Mocaplabel({"export", a.session.string(), "--labels", b.labels.string(), "--format", "bop", "--out", out.string()}, &output), 1);
  EXPECT_NE(output.find("made from session"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out)) << "nothing written";
  // A label run without its session.
  EXPECT_EQ(testing::Mocaplabel({"export", (a.dir / "nowhere").string(), "--labels", a.labels.string(), "--format", "bop", "--out", out.string()}, &output), 1);
  EXPECT_FALSE(fs::exists(out));
  // The output folder holds something else.
  fs::create_directories(a.dir / "busy");
  std::ofstream(a.dir / "busy" / "thesis.tex") << "x";
  EXPECT_EQ(testing::Mocaplabel({"export", a.session.string(), "--format", "bop", "--out", (a.dir / "busy").string()}, &output), 1);
  EXPECT_TRUE(fs::exists(a.dir / "busy" / "thesis.tex"));
  // An object id that means another object in the second session: relabel b with a library where the id moved.
  pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(b.session / "objects.yaml");
  library.objects[0].id = 900;
  pipeline::WriteObjectLibrary(library, b.session / "moved.yaml");  // meshes relative to the session, as written
  ASSERT_EQ(testing::Mocaplabel({"label", b.session.string(), "--objects", (b.session / "moved.yaml").string(), "--out", (b.dir / "L2").string()}, &output), 0) << output;
  EXPECT_EQ(testing::Mocaplabel({"export", a.session.string(), b.session.string(), "--labels", a.labels.string(), "--labels",
                                 (b.dir / "L2").string(), "--format", "bop", "--out", out.string()}, &output), 1);
  EXPECT_NE(output.find("one id per object"), std::string::npos) << output;
  EXPECT_FALSE(fs::exists(out));
  // Two sessions with one library export together; an unchanged re-export writes nothing.
  ASSERT_EQ(testing::Mocaplabel({"export", a.session.string(), b.session.string(), "--format", "bop", "--out", out.string(), "--json"}, &output), 0) << output;
  EXPECT_TRUE(fs::exists(out / "train/000002/scene_gt.json") || fs::exists(out / "val/000002/scene_gt.json") ||
              fs::exists(out / "test/000002/scene_gt.json"));
  const auto mtime = fs::last_write_time(out / "export.json");
  ASSERT_EQ(testing::Mocaplabel({"export", a.session.string(), b.session.string(), "--format", "bop", "--out", out.string()}, &output), 0) << output;
  EXPECT_NE(output.find("up to date"), std::string::npos) << output;
  EXPECT_EQ(fs::last_write_time(out / "export.json"), mtime);
  fs::remove_all(a.dir), fs::remove_all(b.dir);
}

TEST(ExportErrors, AFullDiskSaysSoAndLeavesNothing) {
  const testing::LabelledSession s = testing::MakeLabelledSession("full_disk", 6);
  const fs::path mount_point = s.dir / "disk";
  fs::create_directories(mount_point);
  const std::string result = testing::RunOnFullDiskInChild(mount_point, [&](const testing::SayFn& say) {
    const fs::path out = mount_point / "D";
    std::string error;
    ExportInput input;
    input.session_dir = s.session;
    try {  // images copied (no hard link across file systems) onto a 1 MiB disk
      RunExport({input}, ExportOptions{}, out, {"mocaplabel", "export"});
    } catch (const InputError& e) {
      error = e.what();
    }
    if (error.find("No space left on device") == std::string::npos) say("FAIL expected ENOSPC, got: " + error);
    if (fs::exists(out) || fs::exists(fs::path(out).concat(".partial"))) say("FAIL a dataset was left at " + out.string());
    say("OK " + error);
  });
  if (result.rfind("SKIP", 0) == 0) GTEST_SKIP() << result;
  EXPECT_EQ(result.substr(0, 3), "OK ") << result;
  fs::remove_all(s.dir);
}

}  // namespace
}  // namespace mocap
