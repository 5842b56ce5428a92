#include "capture/kinect/fakenect_recording.h"

#include <libfreenect.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "capture/kinect/kinect1_depth.h"
#include "core/check.h"
#include "tum_recording.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

cv::Mat Gradient() {
  cv::Mat bgr(480, 640, CV_8UC3);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) bgr.at<cv::Vec3b>(v, u) = cv::Vec3b(u % 256, v % 256, (u + v) % 256);
  return bgr;
}

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(FakenectRecording, WritesTheFakenectLayout) {
  const fs::path dir = testing::FreshDir("writer_layout") / "rec";
  cv::Mat depth_mm(480, 640, CV_16UC1, cv::Scalar(1500));
  depth_mm.at<uint16_t>(0, 0) = 0;      // no value
  depth_mm.at<uint16_t>(0, 1) = 200;    // nearer than 0.30 m: not representable
  depth_mm.at<uint16_t>(0, 2) = 12000;  // beyond 10 m
  TiltSample tilt;
  tilt.accel_raw[1] = -819;
  tilt.tilt_deg = 2.5;
  FakenectRecordingWriter writer(dir);
  const FakenectFrameStats stats = writer.AddFrame(Gradient(), depth_mm, (uint64_t{1} << 32) + 77, 12.5, tilt);
  writer.Close();
  EXPECT_EQ(stats.depth_no_value, 1);
  EXPECT_EQ(stats.depth_unrepresentable, 2);
  EXPECT_EQ(stats.depth_valid, 640 * 480 - 3);

  std::ifstream index(dir / "INDEX.txt");
  std::vector<std::string> lines;
  for (std::string line; std::getline(index, line);) lines.push_back(line);
  // The accelerometer sample comes first so the frame replayed after it carries it; ticks are mod 2^32.
  ASSERT_EQ(lines, (std::vector<std::string>{"a-12.500000-77.dump", "d-12.500000-77.pgm", "r-12.500000-77.ppm"}));
  const std::string depth_bytes = Bytes(dir / lines[1]);
  ASSERT_EQ(depth_bytes.size(), std::string("P5 640 480 65535\n").size() + 640 * 480 * 2);
  EXPECT_EQ(depth_bytes.substr(0, 17), "P5 640 480 65535\n");
  // Little-endian raw disparity: pixel (0,3) holds the code of 1.5 m.
  const uint16_t code = DepthMToRaw11(1.5);
  EXPECT_EQ(static_cast<uint8_t>(depth_bytes[17 + 6]), code & 0xff);
  EXPECT_EQ(static_cast<uint8_t>(depth_bytes[17 + 7]), code >> 8);
  EXPECT_EQ(Bytes(dir / lines[0]).size(), sizeof(freenect_raw_tilt_state));
  EXPECT_EQ(Bytes(dir / lines[2]).substr(0, 15), "P6 640 480 255\n");
}

TEST(FakenectRecording, ReaderReturnsWhatWasWritten) {
  const fs::path dir = testing::FreshDir("writer_roundtrip") / "rec";
  cv::Mat depth_m(480, 640, CV_32FC1, cv::Scalar(2.0f));
  const RecordingCamera camera{PinholeCamera{640, 480, 525, 525, 319.5, 239.5, {}}, true};
  {
    FakenectRecordingWriter writer(dir, camera);
    writer.AddFrame(Gradient(), depth_m, 100, 1.0);
    writer.AddFrame(Gradient(), depth_m, 2'000'100, 1.0333);
  }
  const auto entries = ReadFakenectIndex(dir);
  ASSERT_EQ(entries.size(), 4u);
  EXPECT_EQ(entries[2].type, 'd');
  EXPECT_EQ(entries[2].ticks, 2'000'100u);
  EXPECT_DOUBLE_EQ(entries[2].host_time_s, 1.0333);
  const cv::Mat raw = ReadFakenectDepthRaw(entries[0].file);
  EXPECT_EQ(raw.at<uint16_t>(240, 320), DepthMToRaw11(2.0));
  EXPECT_EQ(cv::norm(ReadFakenectColorBgr(entries[1].file), Gradient(), cv::NORM_INF), 0.0);
  const auto read_camera = ReadRecordingCamera(dir);
  ASSERT_TRUE(read_camera);
  EXPECT_TRUE(read_camera->depth_registered);
  EXPECT_DOUBLE_EQ(read_camera->depth_camera.cx, 319.5);
}

TEST(FakenectRecording, RejectsBadInputWithItsPlace) {
  const fs::path dir = testing::FreshDir("writer_bad") / "rec";
  FakenectRecordingWriter writer(dir);
  const cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(1000));
  EXPECT_THROW(writer.AddFrame(cv::Mat(240, 320, CV_8UC3), depth, 0, 0.0), InputError);
  EXPECT_THROW(writer.AddFrame(Gradient(), cv::Mat(480, 640, CV_8UC1), 0, 0.0), InputError);
  writer.AddFrame(Gradient(), depth, 0, 5.0);
  try {
    writer.AddFrame(Gradient(), depth, 1, 4.0);
    FAIL() << "a host time going backwards was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("frame 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(writer.AddFrame(Gradient(), depth, 0, 5.0), InputError);  // same name as frame 0
  writer.Close();
  EXPECT_THROW(FakenectRecordingWriter again(dir), InputError);  // INDEX.txt already there
}

TEST(FakenectRecording, ReaderNamesTheBadLine) {
  const fs::path dir = testing::FreshDir("reader_bad");
  std::ofstream(dir / "INDEX.txt") << "garbage line\n";
  try {
    ReadFakenectIndex(dir);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("INDEX.txt:1"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "d-1.000000-5.pgm") << "P5 320 240 65535\n";
  EXPECT_THROW(ReadFakenectDepthRaw(dir / "d-1.000000-5.pgm"), InputError);
  std::ofstream(dir / kRecordingCameraFile) << "{\"depth_camera\": 3}";
  EXPECT_THROW(ReadRecordingCamera(dir), InputError);
}

}  // namespace
}  // namespace mocap::capture
