// validate/depth_time.h: labels moved to the depth's exposure of a record whose depth was taken apart
// from its colour (CameraFrameRecord::depth_stamp_ns, a Kinect v2), on a session written to disk and
// read back, so the session format's field is part of what is tested.
#include "validate/depth_time.h"

#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "session/writer.h"
#include "session_fixture.h"

namespace mocap {
namespace {

constexpr int64_t kFrameNs = 33'333'333, kDelayNs = 15'000'000;

/// Three frames 33 ms apart; frame 1's depth 15 ms before its colour (or at it, when `delay_ns` is 0).
std::filesystem::path WriteSession(const std::string& name, int64_t delay_ns) {
  const std::filesystem::path dir = testing::FreshTempDir(name) / "S";
  SessionManifest manifest;
  CameraStreamInfo camera;
  camera.name = "kinect2";
  camera.model = "kinect2";
  camera.color_camera = camera.depth_camera = PinholeCamera{64, 48, 50.0, 50.0, 31.5, 23.5, {}};
  manifest.cameras.push_back(camera);
  auto writer = SessionWriter::Create(dir, manifest);
  for (int64_t i = 0; i < 3; ++i) {
    CameraFrameRecord record;
    record.frame = i;
    record.stamp_ns = 1'000'000'000 + i * kFrameNs;
    if (i == 1 && delay_ns != 0) record.depth_stamp_ns = record.stamp_ns - delay_ns;
    writer->WriteCameraFrame("kinect2", record, cv::Mat(), cv::Mat(48, 64, CV_16UC1, cv::Scalar(1000)));
  }
  writer->Close();
  return dir;
}

RecordCheck Label(int64_t index, int instance, const Eigen::Vector3d& t_m) {
  RecordCheck r;
  r.camera = "kinect2";
  r.index = index;
  r.stamp_ns = 1'000'000'000 + index * kFrameNs;
  r.instance = instance;
  r.T_camera_object_label = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * index, Eigen::Vector3d::UnitZ())), t_m);
  return r;
}

TEST(DepthTime, TheSessionKeepsTheDepthStampAndALabelMovesToIt) {
  const SessionReader session = SessionReader::Open(WriteSession("depth_time_moves", kDelayNs));
  EXPECT_EQ(session.frame("kinect2", 1).record.depth_stamp_ns, 1'000'000'000 + kFrameNs - kDelayNs);
  EXPECT_EQ(session.frame("kinect2", 0).record.depth_time_ns(), session.frame("kinect2", 0).record.stamp_ns);
  // An object moving 0.3 m/s along x (1 cm per frame) and turning 0.3 rad per frame.
  std::vector<RecordCheck> records;
  for (int64_t i = 0; i < 3; ++i) records.push_back(Label(i, 1, Eigen::Vector3d(0.01 * i, 0.0, 1.0)));
  const DepthTimeMoves moves = MoveLabelsToDepthTime(session, records);
  EXPECT_EQ(moves.moved, 1);
  EXPECT_EQ(moves.unmovable, 0);
  // Frame 1's depth is 15 of the 33.3 ms back towards frame 0: x = 1 cm - 0.45 cm, angle 0.3 - 0.135 rad.
  const double back = static_cast<double>(kDelayNs) / kFrameNs;
  EXPECT_NEAR(records[1].T_camera_object_label.translation().x(), 0.01 * (1.0 - back), 1e-9);
  EXPECT_NEAR(Eigen::AngleAxisd(records[1].T_camera_object_label.rotation()).angle(), 0.3 * (1.0 - back), 1e-9);
  EXPECT_EQ(records[1].label_shift_ns, -kDelayNs);
  EXPECT_EQ(records[1].depth_offset_ns, -kDelayNs);
  // The neighbours, whose depth was taken with their colour, are as labelled.
  EXPECT_EQ(records[0].T_camera_object_label.translation().x(), 0.0);
  EXPECT_EQ(records[2].label_shift_ns, 0);
  EXPECT_EQ(records[2].depth_offset_ns, 0);
}

TEST(DepthTime, WithoutALabelOnTheDepthsSideTheRecordStaysAndIsCounted) {
  const SessionReader session = SessionReader::Open(WriteSession("depth_time_unmovable", kDelayNs));
  // Instance 2 has no label on frame 0; instance 1's is there.
  std::vector<RecordCheck> records = {Label(1, 2, Eigen::Vector3d(0.01, 0, 1)), Label(2, 2, Eigen::Vector3d(0.02, 0, 1)),
                                      Label(0, 1, Eigen::Vector3d(0, 0, 1)), Label(1, 1, Eigen::Vector3d(0.01, 0, 1))};
  const DepthTimeMoves moves = MoveLabelsToDepthTime(session, records);
  EXPECT_EQ(moves.moved, 1);
  EXPECT_EQ(moves.unmovable, 1);
  EXPECT_EQ(records[0].label_shift_ns, 0);
  EXPECT_EQ(records[0].depth_offset_ns, -kDelayNs);
  EXPECT_EQ(records[0].T_camera_object_label.translation().x(), 0.01);
  EXPECT_EQ(records[3].label_shift_ns, -kDelayNs);
}

TEST(DepthTime, DepthTakenWithColourLeavesEveryLabelAsItWas) {
  const SessionReader session = SessionReader::Open(WriteSession("depth_time_together", 0));
  std::vector<RecordCheck> records;
  for (int64_t i = 0; i < 3; ++i) records.push_back(Label(i, 1, Eigen::Vector3d(0.01 * i, 0, 1)));
  const DepthTimeMoves moves = MoveLabelsToDepthTime(session, records);
  EXPECT_EQ(moves.moved + moves.unmovable, 0);
  for (const RecordCheck& r : records) EXPECT_EQ(r.depth_offset_ns, 0);
  EXPECT_NEAR(records[1].T_camera_object_label.translation().x(), 0.01, 0);
}

TEST(DepthTime, ARecordNamingNoFrameOfTheSessionIsLeftForTheSessionCheckToReport) {
  const SessionReader session = SessionReader::Open(WriteSession("depth_time_foreign", kDelayNs));
  std::vector<RecordCheck> records = {Label(7, 1, Eigen::Vector3d(0, 0, 1)), Label(1, 1, Eigen::Vector3d(0.01, 0, 1))};
  records[1].camera = "kinect9";
  const DepthTimeMoves moves = MoveLabelsToDepthTime(session, records);
  EXPECT_EQ(moves.moved + moves.unmovable, 0);
  for (const RecordCheck& r : records) EXPECT_EQ(r.depth_offset_ns, 0);
}

TEST(DepthTime, ADepthStampSecondsFromItsColourIsAReadingError) {
  const std::filesystem::path dir = WriteSession("depth_time_corrupt", 2'000'000'000);
  try {
    SessionReader::Open(dir);
    FAIL() << "a depth stamp 2 s from its colour was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frames.jsonl"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("depth_stamp_ns"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mocap
