// Must-show checks of the PLUS and Motive importers (all three real PLUS logs and the Motive take
// import; the INVALID frame shows as missing and as a source_status event) and of the BOP importer.
#include <yaml-cpp/yaml.h>

#include "tests/pipeline/label_run_testing.h"

#include <opencv2/imgcodecs.hpp>

#include "session/import/bop_import.h"
#include "session/import/bop_scene.h"
#include "session/import/motive_csv.h"
#include "session/import/plus_mha.h"
#include "session/import/tracker_import.h"
#include "session/reader.h"
#include "session/stats.h"
#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::HasSubstr;
using testing::InputErrorOf;
using testing::RealData;
using testing::ScratchDir;

class PlusImport : public ::testing::TestWithParam<std::string> {};

TEST_P(PlusImport, EveryChannelAndFrameArrives) {
  ScratchDir scratch;
  const auto file = RealData("plus_ndi_tracking/" + GetParam());
  const auto summary = ImportPlus(file, scratch.path() / "S");
  const PlusSequence seq = ReadPlusSequence(file);
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  ASSERT_EQ(reader.manifest().trackers.size(), 1u);
  const auto& tracker = reader.manifest().trackers[0];
  ASSERT_EQ(tracker.bodies.size(), seq.transforms.size());
  EXPECT_EQ(reader.tracker_records("plus").size(), seq.frames.size() * seq.transforms.size());
  EXPECT_EQ(summary.tracker_samples, static_cast<int64_t>(seq.frames.size() * seq.transforms.size()));
  for (size_t k = 0; k < seq.transforms.size(); ++k) {
    EXPECT_EQ(tracker.bodies[k], seq.transforms[k].from_frame);  // all channels map into Tracker
    const auto records = reader.BodyRecords("plus", tracker.bodies[k]);
    ASSERT_EQ(records.size(), seq.frames.size());
    for (size_t i = 0; i < records.size(); i += 37) {
      EXPECT_EQ(records[i].status, seq.transforms[k].samples[i].status);
      EXPECT_EQ(records[i].device_frame, seq.frames[i].frame_number.value_or(static_cast<int64_t>(i)));
      if (HasPose(records[i].status)) {
        EXPECT_LT(TranslationDistanceM(records[i].T_frame_body, seq.transforms[k].samples[i].pose), 1e-9);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(RealLogs, PlusImport,
                         ::testing::Values("ReferenceToRASCalibration.igs.mha", "TransformInterpolationTest.igs.mha",
                                           "WaterTankBottomTranslationTrackerBuffer-trimmed.igs.mha"));

TEST(PlusImportInvalid, InvalidFrameShowsAsMissingAndAsSourceStatus) {
  ScratchDir scratch;
  ImportPlus(RealData("plus_ndi_tracking/TransformInterpolationTest.igs.mha"), scratch.path() / "S");
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  const auto probe = reader.BodyRecords("plus", "Probe");
  std::vector<int64_t> missing_frames;
  for (const auto& r : probe)
    if (r.status == PoseStatus::kMissing) missing_frames.push_back(r.device_frame);
  EXPECT_EQ(missing_frames, std::vector<int64_t>{17});  // Seq_Frame0007, FrameNumber 17
  int invalid_events = 0;
  for (const auto& e : reader.events())
    if (e.kind == "source_status") {
      ++invalid_events;
      EXPECT_EQ(e.stream, "plus/ProbeToTracker");
      EXPECT_THAT(e.detail, HasSubstr("Seq_Frame7: INVALID"));
    }
  EXPECT_EQ(invalid_events, 1);
  const SessionStats stats = ComputeSessionStats(reader);
  for (const auto& body : stats.bodies)
    EXPECT_EQ(body.status_counts.at("missing"), body.body == "Probe" ? 1 : 0) << body.body;
  // Interpolating at the INVALID frame's time is refused with the neighbour's status.
  const auto samples = reader.PoseSamples("plus", "Probe");
  const InterpolatedPose at_invalid = InterpolatePose(samples, samples[7].stamp_ns - 1'000'000);
  EXPECT_EQ(at_invalid.failure, InterpolationFailure::kNeighbourInvalid);
}

TEST(MotiveImport, RigidBodiesWithMissingSamples) {
  ScratchDir scratch;
  const auto file = RealData("optitrack_neon_calib/optitrack_take.csv");
  const auto summary = ImportMotive(file, scratch.path() / "S");
  const MotiveTake take = ReadMotiveCsv(file);
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  EXPECT_EQ(reader.manifest().trackers[0].bodies, (std::vector<std::string>{"NEON_DISPLAY_CALIB", "NEON_FRAME"}));
  for (const auto& body : take.rigid_bodies) {
    const auto records = reader.BodyRecords("motive", body.name);
    ASSERT_EQ(records.size(), 241u);
    int64_t missing = 0;
    for (size_t i = 0; i < records.size(); ++i) {
      missing += records[i].status == PoseStatus::kMissing;
      EXPECT_EQ(records[i].status, body.samples[i].status);
      EXPECT_EQ(records[i].device_frame, static_cast<int64_t>(i));
    }
    EXPECT_GT(missing, 0);
    EXPECT_EQ(summary.bodies.at("motive/" + body.name).status_counts.at("missing"), missing);
    EXPECT_LT(RotationDistanceDeg(records[0].T_frame_body, body.samples[0].pose), 1e-9);
  }
  EXPECT_EQ(reader.manifest().extra.at("motive").at("take").at("Rotation Type"), "Quaternion");
}

TEST(BopImport, KnownObjectPosesPerFrameAndObjectList) {
  ScratchDir scratch;
  const auto scene_dir = RealData("bop_lmo_scene2/test/000002");
  const auto models_dir = RealData("bop_lmo_scene2/models");
  const auto summary = ImportBop(scene_dir, models_dir, scratch.path() / "S", BopOptions());
  EXPECT_EQ(summary.camera_records, 10);
  EXPECT_EQ(summary.frames_color_only, 10);
  const BopScene scene = ReadBopScene(scene_dir, models_dir);
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  const auto& manifest = reader.manifest();
  ASSERT_EQ(manifest.cameras.size(), 1u);
  EXPECT_EQ(manifest.cameras[0].color_camera.fx, 572.4114);
  ASSERT_EQ(manifest.trackers.size(), 1u);
  EXPECT_EQ(manifest.trackers[0].frame, "camera:bop");
  EXPECT_EQ(manifest.trackers[0].bodies.size(), 8u);
  ASSERT_EQ(reader.frame_count("bop"), 10);
  for (int64_t i = 0; i < 10; ++i) {
    const auto& entry = reader.frame("bop", i);
    const BopFrame& source = scene.frames[static_cast<size_t>(i)];
    EXPECT_EQ(entry.record.source_id, std::to_string(source.im_id));
    EXPECT_TRUE(entry.color_present);
    EXPECT_EQ(entry.record.stamp_ns, std::llround(source.im_id * 1e9 / 30.0));
    for (const auto& object : source.objects) {
      const auto samples = reader.PoseSamples("objects", BopBodyName(object.obj_id, object.instance));
      const InterpolatedPose pose = InterpolatePose(samples, entry.record.stamp_ns);
      ASSERT_TRUE(pose.ok()) << pose.reason();
      EXPECT_LT(TranslationDistanceM(*pose.pose, object.T_camera_object), 1e-9);
      EXPECT_LT(RotationDistanceDeg(*pose.pose, object.T_camera_object), 1e-6);
    }
  }
  // Frame im_id 3 annotates all 8 objects; a frame with fewer leaves the others missing.
  int64_t missing = 0;
  for (const auto& [name, body] : summary.bodies) missing += body.status_counts.count("missing") ? body.status_counts.at("missing") : 0;
  int64_t absent = 0;
  for (const auto& f : scene.frames) absent += 8 - static_cast<int64_t>(f.objects.size());
  EXPECT_EQ(missing, absent);

  const YAML::Node objects = YAML::LoadFile((scratch.path() / "S" / "objects.yaml").string())["objects"];
  ASSERT_EQ(objects.size(), 8u);
  EXPECT_EQ(objects[0]["id"].as<int>(), 1);
  EXPECT_EQ(objects[0]["name"].as<std::string>(), "obj_000001");
  EXPECT_EQ(objects[0]["unit"].as<std::string>(), "mm");
  EXPECT_TRUE(std::filesystem::exists(objects[0]["mesh"].as<std::string>()));
  EXPECT_EQ(manifest.extra["objects"].size(), 8u);
}

TEST(BopImport, VaryingIntrinsicsSplitCamerasAndInstancesGetTheirOwnBodies) {
  ScratchDir scratch;
  const auto scene = scratch.path() / "000004";
  scratch.Write("models/models_info.json", R"({"1": {"diameter": 80.0}, "2": {"diameter": 50.0}})");
  scratch.Write("models/obj_000001.ply", "ply\n");
  scratch.Write("models/obj_000002.ply", "ply\n");
  scratch.Write("000004/scene_camera.json", R"({
    "1": {"cam_K": [500, 0, 4, 0, 500, 3, 0, 0, 1], "depth_scale": 0.1},
    "2": {"cam_K": [500, 0, 4, 0, 500, 3, 0, 0, 1], "depth_scale": 0.1},
    "3": {"cam_K": [510, 0, 4, 0, 510, 3, 0, 0, 1], "depth_scale": 0.1}})");
  scratch.Write("000004/scene_gt.json", R"({
    "1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 900], "obj_id": 1},
          {"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [20, 0, 950], "obj_id": 1},
          {"cam_R_m2c": [0,-1,0,1,0,0,0,0,1], "cam_t_m2c": [0, 30, 800], "obj_id": 2}],
    "2": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 910], "obj_id": 1}],
    "3": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 920], "obj_id": 1}]})");
  std::filesystem::create_directories(scene / "rgb");
  std::filesystem::create_directories(scene / "depth");
  for (int id = 1; id <= 3; ++id) {
    cv::imwrite((scene / "rgb" / ("00000" + std::to_string(id) + ".png")).string(), cv::Mat(6, 8, CV_8UC3, cv::Scalar(id, 2, 3)));
    cv::imwrite((scene / "depth" / ("00000" + std::to_string(id) + ".png")).string(), cv::Mat(6, 8, CV_16UC1, cv::Scalar(9000)));
  }
  const auto summary = ImportBop(scene, scratch.path() / "models", scratch.path() / "S", BopOptions());
  EXPECT_EQ(summary.frames_with_color_and_depth, 3);
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  const auto& manifest = reader.manifest();
  ASSERT_EQ(manifest.cameras.size(), 2u);
  EXPECT_EQ(manifest.cameras[0].name, "bop");
  EXPECT_EQ(manifest.cameras[1].name, "bop_1");
  EXPECT_EQ(manifest.cameras[1].color_camera.fx, 510.0);
  EXPECT_DOUBLE_EQ(manifest.cameras[0].depth_unit_m, 1e-4);
  EXPECT_EQ(reader.frame_count("bop"), 2);
  EXPECT_EQ(reader.frame_count("bop_1"), 1);
  ASSERT_EQ(manifest.trackers.size(), 2u);
  EXPECT_EQ(manifest.trackers[1].frame, "camera:bop_1");
  EXPECT_EQ(manifest.trackers[0].bodies, (std::vector<std::string>{"obj_000001", "obj_000001_inst1", "obj_000002"}));
  const auto second = reader.BodyRecords("objects", "obj_000001_inst1");
  ASSERT_EQ(second.size(), 2u);
  EXPECT_EQ(second[0].status, PoseStatus::kValid);
  EXPECT_NEAR(second[0].T_frame_body.translation().x(), 0.020, 1e-12);
  EXPECT_EQ(second[1].status, PoseStatus::kMissing);  // frame 2 has one instance only
  // 0.9 m of depth at 0.1 mm per unit.
  EXPECT_NEAR(reader.LoadDepth("bop", 0).at(0, 0), 0.9f, 1e-6f);
}

TEST(BopImport, EmptyOrBadSceneIsRefused) {
  ScratchDir scratch;
  EXPECT_THAT(InputErrorOf([&] { ImportBop(scratch.path() / "nothing", RealData("bop_lmo_scene2/models"), scratch.path() / "S", BopOptions()); }),
              HasSubstr("not a folder"));
  EXPECT_THAT(InputErrorOf([&] { ImportMotive(scratch.Write("x.csv", "Format Version,1.24\n"), scratch.path() / "S"); }),
              HasSubstr("x.csv"));
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "S"));
}

}  // namespace
}  // namespace mocap::import
