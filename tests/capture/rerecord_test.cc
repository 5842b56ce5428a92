// Re-recording a session through the capture daemon in real time: an NDI emulator on loopback serves
// the recorded tracker stream to the daemon's NDI source, a replay source plays the camera stream.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "capture/daemon/rerecord.h"
#include "capture/daemon/session_replay.h"
#include "core/check.h"
#include "session/reader.h"
#include "session/writer.h"
#include "test_dirs.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kMs = 1'000'000;
constexpr int kFrames = 12;          // 30 Hz: 0.4 s
constexpr double kTrackerHz = 100;   // bodies sampled every 10 ms from -50 ms

Rigid3d BodyPose(int body, double t_s) {
  const double a = 0.5 * t_s + body;
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())),
                 Eigen::Vector3d(0.2 * t_s + 0.1 * body, 0.05 * body, -1.5));
}

// A session like a short recording: one RGB-D camera with distinct images per frame, a tracker with
// two moving bodies and one recorded dropout.
fs::path WriteSourceSession(const fs::path& dir) {
  SessionManifest manifest;
  manifest.source = "test";
  CameraStreamInfo camera;
  camera.name = "cam";
  camera.model = "kinect1";
  camera.color_camera = {64, 48, 50, 50, 31.5, 23.5, {}};
  camera.depth_camera = camera.color_camera;
  camera.depth_unit_m = 0.001;
  manifest.cameras.push_back(camera);
  manifest.trackers.push_back({"trk", "polaris", "", "tracker", {"a", "b"}});
  auto writer = SessionWriter::Create(dir, manifest);
  for (int k = 0; k * 1e9 / kTrackerHz <= 0.45e9; ++k) {
    for (int body = 0; body < 2; ++body) {
      TrackerRecord record;
      record.body = body == 0 ? "a" : "b";
      record.device_frame = k;
      record.stamp_ns = static_cast<int64_t>(k * 1e9 / kTrackerHz) - 50 * kMs;
      record.status = body == 1 && k == 20 ? PoseStatus::kMissing : PoseStatus::kValid;
      record.T_frame_body = BodyPose(body, record.stamp_ns * 1e-9);
      writer->WriteTrackerSample("trk", record);
    }
  }
  for (int k = 0; k < kFrames; ++k) {
    cv::Mat color(48, 64, CV_8UC3), depth(48, 64, CV_16UC1);
    cv::randu(color, 0, 256);
    depth.setTo(500 + 10 * k);
    CameraFrameRecord record;
    record.frame = 100 + k;
    record.device_ticks = 2'000'000LL * k;
    record.stamp_ns = static_cast<int64_t>(k * 1e9 / 30);
    writer->WriteCameraFrame("cam", record, color, depth);
  }
  writer->Close();
  return dir;
}

TEST(Rerecord, DaemonRecordsEveryFrameAndTheTrackerWithTheRecordingsTiming) {
  const fs::path root = testing::FreshCaptureDir("rerecord");
  const fs::path source_dir = WriteSourceSession(root / "source");
  RerecordOptions options;
  options.source_session = source_dir;
  options.out_session = root / "again";
  options.lead_in_s = 0.5;
  const RerecordResult result = RerecordSession(options);
  ASSERT_TRUE(result.complete) << result.summary.dump();
  EXPECT_EQ(result.recorded_frames, kFrames);
  EXPECT_NEAR(result.tracker_rate_hz, kTrackerHz, 1e-6);

  const SessionReader source = SessionReader::Open(source_dir), again = SessionReader::Open(options.out_session);
  ASSERT_EQ(again.frame_count("cam"), kFrames);
  // Camera: same frames, ticks and images; stamps shifted by one constant (recording -> host clock).
  const int64_t shift_ns = again.frame("cam", 0).record.stamp_ns - source.frame("cam", 0).record.stamp_ns;
  for (int k = 0; k < kFrames; ++k) {
    const CameraFrameRecord &a = source.frame("cam", k).record, &b = again.frame("cam", k).record;
    EXPECT_EQ(b.frame, a.frame);
    EXPECT_EQ(b.device_ticks, a.device_ticks);
    EXPECT_EQ(b.stamp_ns - a.stamp_ns, shift_ns) << "frame " << k;
    EXPECT_EQ(cv::norm(source.LoadColor("cam", k), again.LoadColor("cam", k), cv::NORM_INF), 0);
    EXPECT_EQ(source.LoadDepth("cam", k).data, again.LoadDepth("cam", k).data);
  }
  // Tracker: each valid sample is the body's pose at (its stamp - shift - the poll delay), the poll
  // delay being under a few poll periods (10 ms frames polled at 800 Hz; loaded machines stretch it).
  int valid = 0;
  for (int body = 0; body < 2; ++body) {
    for (const PoseSample& s : again.PoseSamples("trk", body == 0 ? "a" : "b")) {
      if (s.status != PoseStatus::kValid) continue;
      ++valid;
      const double t_s = (s.stamp_ns - shift_ns) * 1e-9;
      // x = 0.2 m/s * t + 0.1 m * body gives the time the served pose is of.
      const double served_s = (s.pose.translation().x() - 0.1 * body) / 0.2;
      EXPECT_LT((BodyPose(body, served_s).translation() - s.pose.translation()).norm(), 1e-6);
      EXPECT_LT(BodyPose(body, served_s).rotation().angularDistance(s.pose.rotation()), 1e-6);
      const double delay_ms = (t_s - served_s) * 1e3;
      EXPECT_GT(delay_ms, -0.01) << "body " << body << " at " << t_s;
      EXPECT_LT(delay_ms, 25.0) << "body " << body << " at " << t_s;
    }
  }
  EXPECT_GT(valid, 2 * 40) << "about 45 valid frames of two bodies expected";
  // The recorded dropout of body b (at 150 ms) comes back as a MISSING sample, and only there.
  int dropouts = 0;
  for (const PoseSample& s : again.PoseSamples("trk", "b")) {
    const double t_ms = (s.stamp_ns - shift_ns) * 1e-6;
    if (s.status == PoseStatus::kMissing && t_ms > -40 && t_ms < 400) {
      ++dropouts;
      EXPECT_NEAR(t_ms, 150 + 10, 10.5) << "a missing sample where none was recorded";
    }
  }
  EXPECT_GE(dropouts, 1);
  EXPECT_EQ(again.manifest().extra.value("rerecorded_from", ""), fs::absolute(source_dir).string());
}

TEST(Rerecord, RefusesSessionsItCannotReplay) {
  const fs::path root = testing::FreshCaptureDir("rerecord_bad");
  SessionManifest camera_only;
  camera_only.source = "test";
  camera_only.cameras.push_back({});
  camera_only.cameras.back().name = "cam";
  camera_only.cameras.back().color_camera = {8, 8, 8, 8, 3.5, 3.5, {}};
  camera_only.cameras.back().depth_camera = camera_only.cameras.back().color_camera;
  SessionWriter::Create(root / "camera_only", camera_only)->Close();
  RerecordOptions options;
  options.source_session = root / "camera_only";
  options.out_session = root / "out";
  EXPECT_THROW(RerecordSession(options), InputError) << "no tracker stream";
  options.source_session = root / "absent";
  EXPECT_THROW(RerecordSession(options), InputError);
  options.out_session = root / "camera_only";
  EXPECT_THROW(RerecordSession(options), InputError) << "output exists";
}

}  // namespace
}  // namespace mocap::capture
