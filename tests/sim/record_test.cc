// sim record, label and score end to end on short pieces of the default scenario (must-show items 2 and
// 3 of the simulated rig): with the true calibration the labels match the truth to the tracker's noise;
// a 5 mm camera-mount error gives ~5 mm, a 20 ms latency error gives what the motion over 20 ms predicts.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "capture/kinect/fakenect_frame_tap.h"
#include "capture/kinect/fakenect_recording.h"
#include "session/reader.h"
#include "pipeline/demo.h"
#include "pipeline/record_stage.h"
#include "pipeline/rig.h"
#include "sim/scene_motion.h"

namespace mocap::sim {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  const fs::path dir = fs::path(testing::TempDir()) / ("mocap_sim_" + name);
  fs::remove_all(dir);
  return dir;
}

/// `frames` frames of the default scenario from `start_s` on (the bottle is carried from 2.6 to 5.0 s).
Scenario Piece(double start_s, int frames) {
  Scenario scenario = DefaultScenario();
  scenario.options.start_s = start_s;
  scenario.options.frame_count = frames;
  return scenario;
}

/// `mocaplabel sim record`'s path: the session with its truth, rig.yaml and objects.yaml.
RecordResult Record(const Scenario& scenario, const fs::path& out, int threads, FrameTap* tap = nullptr) {
  RecordOptions options;
  options.out_dir = out;
  options.threads = threads;
  options.frame_tap = tap;
  options.context.platform = EglPlatform::kSurfaceless;
  return pipeline::RecordSimulatedSession(scenario, nullptr, options).record;
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SimRecord, WritesASessionWithTruthAndTheCalibrationFilesReproducibly) {
  const Scenario scenario = Piece(3.0, 4);
  const fs::path dir_a = TempDir("rec_a");
  capture::FakenectFrameTap fakenect(dir_a / "fakenect");
  const RecordResult a = Record(scenario, dir_a, 2, &fakenect);
  const RecordResult b = Record(scenario, TempDir("rec_b"), 1);
  const SessionReader session = SessionReader::Open(a.session_dir);
  EXPECT_TRUE(session.complete());
  ASSERT_EQ(session.frame_count(a.camera_name), 4);
  EXPECT_EQ(session.manifest().trackers.at(0).bodies.size(), scenario.objects.size() + 1);
  EXPECT_FALSE(session.manifest().software_version.empty()) << "the session does not say which mocaplabel wrote it";
  EXPECT_EQ(session.frame(a.camera_name, 2).record.stamp_ns, a.truth.frames[2].depth_time_ns);
  for (const char* file : {"truth/poses.jsonl", "truth/calibration.json", "truth/instance/000003.png", "rig.yaml",
                           "objects.yaml", "meshes/oil_bottle.ply"})
    EXPECT_TRUE(fs::exists(a.session_dir / file)) << file;
  // Same frames whatever the number of render threads.
  for (int64_t i = 0; i < 4; ++i) {
    EXPECT_EQ(ReadFile(session.ColorPath(a.camera_name, i)), ReadFile(SessionReader::Open(b.session_dir).ColorPath(a.camera_name, i)));
    EXPECT_EQ(ReadFile(session.DepthPath(a.camera_name, i)), ReadFile(SessionReader::Open(b.session_dir).DepthPath(a.camera_name, i)));
  }
  // The fakenect recording holds the same frames, in order, at the session's host times.
  const std::vector<capture::FakenectEntry> entries = capture::ReadFakenectIndex(fakenect.dir());
  ASSERT_EQ(entries.size(), 8u);
  EXPECT_EQ(entries[2].type, 'd');
  EXPECT_NEAR(entries[2].host_time_s, a.truth.frames[1].depth_time_ns * 1e-9, 1e-6);
  const cv::Mat raw = capture::ReadFakenectDepthRaw(fakenect.dir() / entries[2].file);
  const DepthImage depth = session.LoadDepth(a.camera_name, 1);
  ASSERT_EQ(raw.cols, depth.width);
  EXPECT_EQ(raw.at<uint16_t>(240, 320) == kKinect1NoDisparity, depth.at(320, 240) == 0.0f);
  // The rig file carries the given calibration the labeller is to use.
  const pipeline::Rig rig = pipeline::ReadRig(a.session_dir / "rig.yaml");
  ASSERT_EQ(rig.cameras.size(), 1u);
  EXPECT_EQ(rig.tracker_latency_ns, a.truth.given_calibration.tracker_latency_ns);
  // Written with round-trip precision: the file gives back the in-memory calibration exactly.
  EXPECT_EQ(rig.cameras[0].T_body_camera->translation(), a.truth.given_calibration.T_cambody_camera.translation());
  EXPECT_LT(RotationDistanceDeg(*rig.cameras[0].T_body_camera, a.truth.given_calibration.T_cambody_camera), 1e-9);
  EXPECT_EQ(rig.cameras[0].body, scenario.camera_body.name);
}

TEST(SimRecord, Kinect2SessionsHaveUnregisteredDepthAndLabelAgainstTheColourExposure) {
  Scenario scenario = Piece(3.4, 3);
  scenario.options.sensor = SensorKind::kKinect2;
  const fs::path dir = TempDir("kinect2");
  const RecordResult record = Record(scenario, dir / "session", 2);
  const SessionReader session = SessionReader::Open(record.session_dir);
  const CameraStreamInfo& camera = *session.manifest().FindCamera("kinect2");
  EXPECT_FALSE(camera.depth_registered_to_color);
  EXPECT_EQ(session.LoadDepth("kinect2", 0).width, 512);
  EXPECT_EQ(session.LoadColor("kinect2", 0).cols, 1920);
  // The frame is stamped at the colour exposure, 15 +- 4 ms after the depth exposure.
  const FrameTruth& f = record.truth.frames[1];
  EXPECT_EQ(session.frame("kinect2", 1).record.stamp_ns, f.color_time_ns);
  EXPECT_GT(f.color_time_ns - f.depth_time_ns, 2'000'000);
  pipeline::DemoOptions options;
  options.out_dir = dir;
  options.threads = 2;
  options.context.platform = EglPlatform::kSurfaceless;
  const pipeline::LabelScores scores = pipeline::LabelAndScore(record, record.truth.true_calibration, dir / "labels", options);
  // Scored against the colour-exposure truth, the bottle carried at ~0.2 m/s shows no colour delay error.
  EXPECT_LE(scores.pose_err_mm_median, 1.0);
  EXPECT_GE(scores.mask_iou_mean, 0.9);
}

/// Pose error (mm) a latency error of `latency_error_s` predicts for object `object` in each frame:
/// the labeller then shows the object where it is `latency_error_s` later, relative to the camera.
std::vector<double> PredictedLatencyErrorMm(const Scenario& scenario, size_t object, double latency_error_s) {
  const SceneMotion motion(scenario);
  std::vector<double> errors;
  for (int f = 0; f < scenario.options.frame_count; ++f) {
    const double t = scenario.options.start_s + f / scenario.options.frame_rate_hz;
    auto at = [&](double s) { return motion.T_world_camera(s).inverse() * motion.T_world_mesh(object, s); };
    errors.push_back(1000 * (at(t + latency_error_s).translation() - at(t).translation()).norm());
  }
  return errors;
}

double MedianErrorMm(const pipeline::LabelScores& scores, const std::string& object) {
  std::vector<double> errors;
  for (const pipeline::RecordScore& r : scores.per_record)
    if (r.object == object) errors.push_back(r.err_mm);
  return pipeline::Percentile(errors, 50);
}

TEST(SimDemo, TrueCalibrationMeetsTargetsAndInjectedErrorsCostWhatGeometryPredicts) {
  const Scenario scenario = Piece(3.4, 18);  // mid-carry: the bottle moves at ~0.2 m/s
  const fs::path dir = TempDir("errors");
  const RecordResult record = Record(scenario, dir / "session", 2);
  pipeline::DemoOptions options;
  options.out_dir = dir;
  options.threads = 2;
  options.context.platform = EglPlatform::kSurfaceless;
  const RigCalibration& truth = record.truth.true_calibration;

  const pipeline::LabelScores exact = pipeline::LabelAndScore(record, truth, dir / "labels_true", options);
  EXPECT_EQ(exact.frames, 18);
  EXPECT_GE(exact.mask_iou_mean, 0.97);
  EXPECT_LE(exact.pose_err_mm_median, 1.0);
  EXPECT_LE(exact.pose_err_deg_median, 0.2);

  CalibrationErrors mount;
  mount.camera_mount_translation_m = {0.005, 0, 0};
  const pipeline::LabelScores mounted = pipeline::LabelAndScore(record, ApplyCalibrationErrors(truth, mount), dir / "labels_mount", options);
  // Every object moves by the mount error in the camera frame: ~5 mm, plus the tracker's noise.
  EXPECT_NEAR(mounted.pose_err_mm_median, 5.0, 0.6);
  EXPECT_LT(mounted.mask_iou_mean, exact.mask_iou_mean);

  CalibrationErrors late;
  late.latency_ms = 20;
  const pipeline::LabelScores delayed = pipeline::LabelAndScore(record, ApplyCalibrationErrors(truth, late), dir / "labels_latency", options);
  const double predicted = pipeline::Percentile(PredictedLatencyErrorMm(scenario, 3, 0.020), 50);  // oil_bottle
  const double measured = MedianErrorMm(delayed, "oil_bottle");
  EXPECT_GT(predicted, 2.0) << "the piece should be mid-carry";
  EXPECT_NEAR(measured, predicted, 0.15 * predicted + 0.3) << "predicted " << predicted << " mm";
  EXPECT_GT(measured, MedianErrorMm(exact, "oil_bottle") + 1.0);
  std::printf("true calibration: IoU %.4f, %.3f mm, %.3f deg; 5 mm mount: IoU %.4f, %.3f mm; 20 ms latency: bottle %.3f mm "
              "(predicted %.3f mm)\n", exact.mask_iou_mean, exact.pose_err_mm_median, exact.pose_err_deg_median,
              mounted.mask_iou_mean, mounted.pose_err_mm_median, measured, predicted);
}

}  // namespace
}  // namespace mocap::sim
