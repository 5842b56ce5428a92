// Session statistics (`mocaplabel info`) and the reader's tracker look-ups around camera frames.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "session/reader.h"
#include "session/stats.h"
#include "session/writer.h"
#include "session_test_util.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

constexpr int64_t kMs = 1'000'000;

/// TUM seconds with up to 9 decimals ("1311868163.8697") to ns, exactly.
int64_t TumSecondsToNs(const std::string& text) {
  const size_t dot = text.find('.');
  std::string fraction = dot == std::string::npos ? "" : text.substr(dot + 1);
  fraction.resize(9, '0');
  return std::stoll(text.substr(0, dot)) * 1'000'000'000 + std::stoll(fraction);
}

TEST(SessionStats, TumFr2DeskGroundTruthGapsAndDuplicate) {
  // The real fr2/desk mocap trajectory has 6 gaps over 0.5 s and one repeated timestamp (SOURCE.txt).
  std::ifstream in(fs::path(MOCAP_SHARED_DIR) / "realdata/tum_groundtruth_evo/fr2_desk_groundtruth.txt");
  ASSERT_TRUE(in) << "missing ../shared/realdata";
  TempDir tmp;
  SessionManifest manifest;
  manifest.source = "test";
  manifest.trackers = {{"groundtruth", "tum", "", "tracker", {"camera"}}};
  int64_t lines = 0;
  {
    auto writer = SessionWriter::Create(tmp.path() / "S", manifest);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string stamp;
      double tx, ty, tz, qx, qy, qz, qw;
      fields >> stamp >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
      TrackerRecord record;
      record.body = "camera";
      record.device_frame = lines++;
      record.stamp_ns = TumSecondsToNs(stamp);
      record.T_frame_body = Rigid3d::FromQuatXyzw(qx, qy, qz, qw, {tx, ty, tz});
      writer->WriteTrackerSample("groundtruth", record);
    }
  }
  const SessionStats stats = ComputeSessionStats(SessionReader::Open(tmp.path() / "S"));
  ASSERT_EQ(stats.bodies.size(), 1u);
  const BodyStats& body = stats.bodies[0];
  EXPECT_EQ(body.samples, lines);
  EXPECT_EQ(body.samples, 20957);
  EXPECT_EQ(body.timing.duplicates, 1);
  ASSERT_EQ(body.timing.gaps.size(), 6u);
  double longest_s = 0;
  for (const auto& gap : body.timing.gaps) longest_s = std::max(longest_s, (gap.end_ns - gap.start_ns) * 1e-9);
  EXPECT_NEAR(longest_s, 12.0, 0.1);
  EXPECT_EQ(body.status_counts.at("valid"), lines);
  const nlohmann::json json = ToJson(stats);
  EXPECT_EQ(json["tracker_bodies"]["camera"]["samples"], 20957);
  EXPECT_EQ(json["tracker_bodies"]["camera"]["duplicates"], 1);
  EXPECT_EQ(json["tracker_bodies"]["camera"]["gaps"].size(), 6u);
  EXPECT_EQ(json["tracker_bodies"]["camera"]["gaps"][0]["end_ns"].get<int64_t>() -
                json["tracker_bodies"]["camera"]["gaps"][0]["start_ns"].get<int64_t>(),
            body.timing.gaps[0].end_ns - body.timing.gaps[0].start_ns);
  EXPECT_TRUE(json["frames_with_pose"].is_null());  // no camera in this session
}

/// kinect1 at 30 Hz for 12 frames (t = 0, 33.3 ms, ...); body "cam" at 100 Hz from 0 to 200 ms, missing
/// at 100 ms, then nothing until 330 ms: frames in [0, 200] ms interpolate except those next to 100 ms.
class FramePoses : public ::testing::Test {
 protected:
  void SetUp() override {
    auto writer = SessionWriter::Create(dir(), testing::TwoCameraManifest());
    const cv::Mat color = testing::TestColor(0, 8, 6), depth = testing::TestDepth(0, 8, 6);
    for (int i = 0; i < 12; ++i) {
      CameraFrameRecord record{i == 11 ? 13 : i, 0, i * 100 * kMs / 3, "", "", ""};
      if (i == 5) {
        writer->AddCameraFrameFiles("kinect1", record, tmp_.path() / "gone.png", tmp_.path() / "gone_depth.png");
      } else {
        writer->WriteCameraFrame("kinect1", record, color, depth);
      }
    }
    for (int k = 0; k <= 20; ++k) Write(writer.get(), k * 10 * kMs, k == 10 ? PoseStatus::kMissing : PoseStatus::kValid);
    Write(writer.get(), 330 * kMs, PoseStatus::kValid);
    Write(writer.get(), 340 * kMs, PoseStatus::kValid);
    writer->WriteEvent({200 * kMs, "gap", "ndi", "no data for 130 ms"});
  }
  static Rigid3d PoseAt(int64_t stamp_ns) {
    const double t = static_cast<double>(stamp_ns) * 1e-9;
    return Rigid3d::FromRvec({0.3 * t, -0.5 * t, 1.0 + t}, {t, 2 * t, 0.5});
  }
  void Write(SessionWriter* writer, int64_t stamp_ns, PoseStatus status) {
    TrackerRecord record;
    record.body = "cam";
    record.status = status;
    record.device_frame = stamp_ns / (10 * kMs);
    record.stamp_ns = stamp_ns;
    record.T_frame_body = PoseAt(stamp_ns);
    writer->WriteTrackerSample("ndi", record);
  }
  fs::path dir() const { return tmp_.path() / "S"; }
  TempDir tmp_;
};

TEST_F(FramePoses, SamplesAroundAndInterpolatedCameraPose) {
  const SessionReader reader = SessionReader::Open(dir());
  // Frame 4 at 133.33 ms lies between the samples at 130 and 140 ms.
  const SamplesAround around = reader.SamplesAroundFrame("kinect1", 4, "ndi", "cam");
  ASSERT_TRUE(around.before && around.after);
  EXPECT_EQ(around.before->stamp_ns, 130 * kMs);
  EXPECT_EQ(around.after->stamp_ns, 140 * kMs);
  const InterpolatedPose pose = reader.CameraPoseAtFrame("kinect1", 4);
  ASSERT_TRUE(pose.ok()) << pose.reason();
  const double alpha = static_cast<double>(reader.frame("kinect1", 4).record.stamp_ns - 130 * kMs) / (10.0 * kMs);
  const Rigid3d expected = Interpolate(PoseAt(130 * kMs), PoseAt(140 * kMs), alpha) *
                           reader.manifest().cameras[0].T_body_camera;
  EXPECT_LT(TranslationDistanceM(*pose.pose, expected), 1e-12);
  EXPECT_LT(RotationDistanceDeg(*pose.pose, expected), 1e-9);
  // Frame 3 at 100 ms sits on the missing sample: refused with a reason.
  const InterpolatedPose refused = reader.CameraPoseAtFrame("kinect1", 3);
  EXPECT_EQ(refused.failure, InterpolationFailure::kNeighbourInvalid);
  // Frame 0 precedes nothing; the first sample is at 0 ms, so it is an exact hit.
  const SamplesAround first = reader.SamplesAroundFrame("kinect1", 0, "ndi", "cam");
  EXPECT_TRUE(first.before && first.before->stamp_ns == 0);
  // The tum camera has no body.
  EXPECT_EQ(reader.CameraPoseAtFrame("tum", 0).failure, InterpolationFailure::kEmptyStream);
}

TEST_F(FramePoses, StatsCountFramesPosesGapsAndMissingFiles) {
  const SessionStats stats = ComputeSessionStats(SessionReader::Open(dir()));
  ASSERT_EQ(stats.cameras.size(), 2u);
  const CameraStats& camera = stats.cameras[0];
  EXPECT_EQ(camera.records, 12);
  EXPECT_EQ(camera.frames, 11);  // frame 5's files are listed but absent
  EXPECT_EQ(stats.frames, 11);
  ASSERT_EQ(stats.missing_files.size(), 2u);
  EXPECT_EQ(stats.missing_files[0], "cameras/kinect1/color/000005.png");
  EXPECT_EQ(camera.dropped_frames, 2);  // frame numbers 11 and 12 never came
  // With poses: frames at 0, 33, 67, 133, 200(exact hit... at 200 the next sample is 330 ms away, but an
  // exact hit needs no neighbour) -> count by the library's rule rather than by hand where it is subtle.
  int64_t expected_with_pose = 0;
  const SessionReader reader = SessionReader::Open(dir());
  for (int64_t i = 0; i < 12; ++i)
    if (reader.frame("kinect1", i).color_present) expected_with_pose += reader.CameraPoseAtFrame("kinect1", i).ok();
  ASSERT_TRUE(stats.frames_with_pose.has_value());
  EXPECT_EQ(*stats.frames_with_pose, expected_with_pose);
  EXPECT_GE(expected_with_pose, 5);   // 0, 33, 67, 133, 167 ms at least
  EXPECT_LE(expected_with_pose, 7);   // 100 ms refused, 233 ms onwards beyond the 50 ms limit or the end
  EXPECT_EQ(camera.pose_failures.count("neighbour_invalid") + camera.pose_failures.count("gap_too_long") +
                camera.pose_failures.count("after_end"),
            camera.pose_failures.size());

  const BodyStats& cam = stats.bodies[0];
  EXPECT_EQ(cam.body, "cam");
  EXPECT_EQ(cam.samples, 23);
  EXPECT_EQ(cam.status_counts.at("missing"), 1);
  EXPECT_EQ(cam.status_counts.at("valid"), 22);
  ASSERT_EQ(cam.dropouts.size(), 1u);
  EXPECT_EQ(cam.dropouts[0].start_ns, 100 * kMs);
  EXPECT_EQ(cam.dropped_frames, 12);  // tracker frames 21..32 never came
  SessionStatsOptions options;
  options.gap_limit_ns = 100 * kMs;
  const SessionStats tight = ComputeSessionStats(reader, options);
  ASSERT_EQ(tight.bodies[0].timing.gaps.size(), 1u);
  EXPECT_EQ(tight.bodies[0].timing.gaps[0].start_ns, 200 * kMs);
  EXPECT_EQ(tight.bodies[0].timing.gaps[0].end_ns, 330 * kMs);
  EXPECT_EQ(stats.event_counts.at("gap"), 1);

  const nlohmann::json json = ToJson(stats);
  EXPECT_EQ(json["frames"], 11);
  EXPECT_EQ(json["frames_with_pose"], expected_with_pose);
  EXPECT_EQ(json["missing_files"], 2);
  EXPECT_EQ(json["missing_file_list"].size(), 2u);
  EXPECT_EQ(json["tracker_bodies"]["cam"]["status_counts"]["missing"], 1);
  EXPECT_EQ(json["tracker_bodies"]["obj"]["samples"], 0);
  EXPECT_NE(FormatSessionStats(stats).find("missing image files: 2"), std::string::npos);
}

}  // namespace
}  // namespace mocap
