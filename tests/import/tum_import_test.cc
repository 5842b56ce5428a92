// Must-show checks of the TUM importer: frames, depth, missing files and camera poses in the session,
// the poses checked against a SLERP computed here from groundtruth.txt; and fr2/desk's gaps and
// duplicated stamp reported, with interpolation inside a gap refused.
#include "session/import/tum_import.h"

#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "session/reader.h"
#include "session/stats.h"
#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::HasSubstr;
using testing::InputErrorOf;
using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

struct GtLine {
  long double t;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
};

// groundtruth.txt read here with a plain stream, independently of the importer.
std::vector<GtLine> ReadGroundTruthByHand(const std::filesystem::path& file) {
  std::vector<GtLine> lines;
  std::istringstream in(ReadAll(file));
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream f(line);
    std::string t;
    double tx, ty, tz, qx, qy, qz, qw;
    f >> t >> tx >> ty >> tz >> qx >> qy >> qz >> qw;
    lines.push_back({std::stold(t), {tx, ty, tz}, Eigen::Quaterniond(qw, qx, qy, qz).normalized()});
  }
  return lines;
}

TEST(TumImport, Fr1DeskNineFramesWithDepthAndInterpolatedPoses) {
  ScratchDir scratch;
  const auto session = scratch.path() / "S";
  TumImportOptions options;
  options.software_version = "test";
  const auto summary = ImportTum(RealData("tum_fr1_desk_9frames"), session, options);
  EXPECT_EQ(summary.frames_with_color_and_depth, 9);
  EXPECT_EQ(summary.missing_files, (613 - 9) + (595 - 9));  // every listed image is in some record

  const SessionReader reader = SessionReader::Open(session);
  ASSERT_EQ(reader.manifest().cameras.size(), 1u);
  const auto& camera = reader.manifest().cameras[0];
  EXPECT_EQ(camera.color_camera.fx, 517.3);  // rgb.txt names freiburg1: TUM's fr1 calibration
  EXPECT_DOUBLE_EQ(camera.depth_unit_m, 1.0 / 5000.0);

  const SessionStats stats = ComputeSessionStats(reader);
  EXPECT_EQ(stats.frames, 9);
  ASSERT_TRUE(stats.frames_with_pose.has_value());
  EXPECT_EQ(*stats.frames_with_pose, 9);
  EXPECT_EQ(static_cast<int64_t>(stats.missing_files.size()), summary.missing_files);

  const auto gt = ReadGroundTruthByHand(RealData("tum_fr1_desk_9frames/groundtruth.txt"));
  int checked = 0;
  for (int64_t i = 0; i < reader.frame_count(camera.name); ++i) {
    const auto& entry = reader.frame(camera.name, i);
    if (!(entry.color_present && entry.depth_present)) continue;
    // The source id is the rgb.txt stamp, which also names the image file.
    EXPECT_TRUE(std::filesystem::exists(RealData("tum_fr1_desk_9frames/rgb/" + entry.record.source_id + ".png")));
    const long double t = std::stold(entry.record.source_id);
    const auto after = std::find_if(gt.begin(), gt.end(), [&](const GtLine& l) { return l.t > t; });
    ASSERT_TRUE(after != gt.begin() && after != gt.end());
    const GtLine& a = *(after - 1);
    const GtLine& b = *after;
    const double alpha = static_cast<double>((t - a.t) / (b.t - a.t));
    const Eigen::Quaterniond q_expected = a.q.slerp(alpha, b.q);
    const Eigen::Vector3d p_expected = (1 - alpha) * a.p + alpha * b.p;
    const InterpolatedPose pose = reader.CameraPoseAtFrame(camera.name, i);
    ASSERT_TRUE(pose.ok()) << pose.reason();
    EXPECT_LT((pose.pose->translation() - p_expected).norm(), 1e-5);  // 0.01 mm
    EXPECT_LT(RotationDistanceDeg(*pose.pose, Rigid3d(q_expected, p_expected)), 1e-3);
    // Depth kept losslessly: the session's depth equals the source PNG / 5000.
    const DepthImage depth = reader.LoadDepth(camera.name, i);
    const cv::Mat raw = cv::imread(reader.DepthPath(camera.name, i).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(raw.type(), CV_16UC1);
    EXPECT_FLOAT_EQ(depth.at(320, 240), static_cast<float>(raw.at<uint16_t>(240, 320) / 5000.0));
    ++checked;
  }
  EXPECT_EQ(checked, 9);
}

TEST(TumImport, Fr2DeskGapsAndDuplicateAreReportedAndGapsRefused) {
  ScratchDir scratch;
  const auto session = scratch.path() / "S";
  const auto summary = ImportTum(RealData("tum_groundtruth_evo/fr2_desk_groundtruth.txt"), session, {});
  const auto& body = summary.bodies.at("groundtruth/camera");
  EXPECT_EQ(body.samples, 20957);
  EXPECT_EQ(body.duplicate_stamps, 1);
  ASSERT_EQ(body.gaps.size(), 6u);

  const SessionReader reader = SessionReader::Open(session);
  const SessionStats stats = ComputeSessionStats(reader);
  ASSERT_EQ(stats.bodies.size(), 1u);
  EXPECT_EQ(stats.bodies[0].timing.duplicates, 1);
  EXPECT_EQ(stats.bodies[0].timing.gaps.size(), 6u);
  EXPECT_EQ(stats.event_counts.at("gap"), 6);
  EXPECT_EQ(stats.event_counts.at("duplicate_stamp"), 1);
  const nlohmann::json info = ToJson(stats);
  EXPECT_EQ(info["tracker_bodies"]["camera"]["duplicates"], 1);
  EXPECT_EQ(info["tracker_bodies"]["camera"]["gaps"].size(), 6u);

  // The longest gap is 12 s; a time in its middle is refused, even with a 1 s bridging limit.
  const auto longest = *std::max_element(body.gaps.begin(), body.gaps.end(), [](const auto& x, const auto& y) {
    return x.end_ns - x.start_ns < y.end_ns - y.start_ns;
  });
  EXPECT_NEAR(static_cast<double>(longest.end_ns - longest.start_ns) * 1e-9, 12.0, 0.1);
  const auto samples = reader.PoseSamples("groundtruth", "camera");
  const int64_t middle = (longest.start_ns + longest.end_ns) / 2;
  for (int64_t max_gap_ns : {int64_t{50'000'000}, int64_t{1'000'000'000}}) {
    const InterpolatedPose pose = InterpolatePose(samples, middle, {.max_gap_ns = max_gap_ns});
    EXPECT_FALSE(pose.ok());
    EXPECT_EQ(pose.failure, InterpolationFailure::kGapTooLong);
    EXPECT_THAT(pose.reason(), HasSubstr("gap"));
  }
  // Just inside a normal stretch it interpolates.
  EXPECT_TRUE(InterpolatePose(samples, samples[100].stamp_ns + 1'000'000).ok());
}

TEST(TumImport, IntrinsicsOverrideAndBadOutput) {
  ScratchDir scratch;
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = camera.fy = 525;
  camera.cx = 319.5;
  camera.cy = 239.5;
  TumImportOptions options;
  options.camera = camera;
  ImportTum(RealData("tum_fr1_desk_9frames"), scratch.path() / "S", options);
  EXPECT_EQ(SessionReader::Open(scratch.path() / "S").manifest().cameras[0].color_camera.fx, 525.0);
  // The folder now exists and is not empty.
  EXPECT_THAT(InputErrorOf([&] { ImportTum(RealData("tum_fr1_desk_9frames"), scratch.path() / "S"); }),
              HasSubstr("not empty"));
  // A source with a corrupt line fails before any session is created.
  scratch.Write("bad/rgb.txt", "1.0 rgb/1.png\n");
  scratch.Write("bad/depth.txt", "1.0 depth/1.png\n");
  scratch.Write("bad/groundtruth.txt", "1.0 0 0 0 0 0 0\n");
  EXPECT_THAT(InputErrorOf([&] { ImportTum(scratch.path() / "bad", scratch.path() / "T"); }),
              HasSubstr("groundtruth.txt:1: expected"));
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "T"));
}

TEST(TumImport, ImageCutInHalfIsRefusedBeforeTheSessionIsCreated) {
  ScratchDir scratch;
  const auto src = RealData("tum_fr1_desk_9frames");
  const std::string rgb = ReadAll(src / "rgb/1305031453.359684.png");
  const std::string depth = ReadAll(src / "depth/1305031453.374112.png");
  scratch.Write("seq/rgb.txt", "# file: 'rgbd_dataset_freiburg1_desk.bag'\n1305031453.359684 rgb/1305031453.359684.png\n");
  scratch.Write("seq/depth.txt", "1305031453.374112 depth/1305031453.374112.png\n");
  scratch.Write("seq/groundtruth.txt", "1305031453.3500 0 0 0 0 0 0 1\n1305031453.3600 0 0 0 0 0 0 1\n");
  scratch.Write("seq/rgb/1305031453.359684.png", rgb);
  scratch.Write("seq/depth/1305031453.374112.png", depth.substr(0, depth.size() / 2));
  EXPECT_THAT(InputErrorOf([&] { ImportTum(scratch.path() / "seq", scratch.path() / "S"); }),
              HasSubstr("1305031453.374112.png: byte " + std::to_string(depth.size() / 2) + ": PNG is truncated"));
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "S"));
  // Whole again, the same folder imports: one frame with colour and depth.
  scratch.Write("seq/depth/1305031453.374112.png", depth);
  EXPECT_EQ(ImportTum(scratch.path() / "seq", scratch.path() / "S").frames_with_color_and_depth, 1);
}

}  // namespace
}  // namespace mocap::import
