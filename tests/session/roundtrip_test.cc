// Everything written by SessionWriter reads back identically through SessionReader.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "session/reader.h"
#include "session/writer.h"
#include "session_test_util.h"

namespace mocap {
namespace {

using testing::TempDir;
using testing::TestColor;
using testing::TestDepth;
using testing::TwoCameraManifest;

TrackerRecord Sample(const std::string& body, int64_t i, PoseStatus status = PoseStatus::kValid) {
  TrackerRecord record;
  record.body = body;
  record.status = status;
  record.device_frame = 1000 + i;
  record.device_ticks = 37'000 + 600'000 * i;
  record.stamp_ns = 5'000'000'000 + i * 10'000'000;
  record.T_frame_body = Rigid3d::FromRvec({0.01 * i, 0.2, -0.1}, {0.1 * i, 0.5, 1.0 / 3.0});
  record.rms_error_m = 0.00021 * (1 + i % 3);
  record.port_status = 0x31u + static_cast<uint32_t>(i);
  return record;
}

void ExpectSameRecord(const TrackerRecord& a, const TrackerRecord& b) {
  EXPECT_EQ(a.body, b.body);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.device_frame, b.device_frame);
  EXPECT_EQ(a.device_ticks, b.device_ticks);
  EXPECT_EQ(a.stamp_ns, b.stamp_ns);
  EXPECT_EQ(a.rms_error_m, b.rms_error_m);
  EXPECT_EQ(a.port_status, b.port_status);
  if (CarriesPose(a.status)) {
    EXPECT_LT(TranslationDistanceM(a.T_frame_body, b.T_frame_body), 1e-15);
    EXPECT_LT(RotationDistanceDeg(a.T_frame_body, b.T_frame_body), 1e-9);
  }
}

TEST(SessionRoundTrip, ManifestRecordsAndImages) {
  TempDir tmp;
  const auto dir = tmp.path() / "S";
  const SessionManifest manifest = TwoCameraManifest();
  ClockFit fit;
  fit.ticks_origin = 123456789;
  fit.offset_ns = 1.5e9 + 0.25;
  fit.ns_per_tick = 1e9 / 60e6;
  fit.residual_rms_ns = 12345.5;
  fit.residual_max_ns = 99999.0;
  fit.samples = 300;
  fit.inliers = 297;
  fit.iterations = 6;
  std::vector<TrackerRecord> written;
  {
    auto writer = SessionWriter::Create(dir, manifest);
    for (int i = 0; i < 5; ++i) {
      CameraFrameRecord record{i, 600'000 * i, 5'000'000'000 + 33'333'333LL * i, "", "", ""};
      writer->WriteCameraFrame("kinect1", record, TestColor(i), TestDepth(i));
      for (const char* body : {"cam", "obj"}) {
        written.push_back(Sample(body, i, i == 3 ? PoseStatus::kMissing : PoseStatus::kValid));
        writer->WriteTrackerSample("ndi", written.back());
      }
    }
    // Kinect2-style: colour-only and depth-only records with their own stamps; float metres depth.
    writer->WriteCameraFrame("tum", {7, 0, 10, "1305031102.175304", "", ""}, TestColor(9), cv::Mat());
    cv::Mat metres;
    TestDepth(3).convertTo(metres, CV_32FC1, 1.0 / 5000.0);
    writer->WriteCameraFrame("tum", {8, 0, 20, "1305031102.160407", "", ""}, cv::Mat(), metres);
    writer->WriteTrackerSample("known", Sample("obj_000001", 0));
    writer->WriteEvent({42, "reconnect", "ndi", "port 2 came back"});
    writer->UpdateClockFit("kinect1", fit);
    writer->Close();
  }
  const SessionReader reader = SessionReader::Open(dir);
  EXPECT_TRUE(reader.complete());
  const SessionManifest& read = reader.manifest();
  ASSERT_EQ(read.cameras.size(), 2u);
  EXPECT_EQ(read.cameras[0].serial, "A00362A10251047A");
  EXPECT_EQ(read.cameras[1].depth_unit_m, 1.0 / 5000.0);  // exact: JSON keeps the shortest round-trip form
  EXPECT_EQ(read.cameras[0].color_camera.dist, manifest.cameras[0].color_camera.dist);
  EXPECT_EQ(read.cameras[0].color_camera.fx, 517.3);
  EXPECT_FALSE(read.cameras[1].depth_registered_to_color);
  EXPECT_LT(TranslationDistanceM(read.cameras[1].T_color_depth, manifest.cameras[1].T_color_depth), 1e-15);
  EXPECT_LT(RotationDistanceDeg(read.cameras[0].T_body_camera, manifest.cameras[0].T_body_camera), 1e-9);
  EXPECT_EQ(read.trackers[1].frame, "camera:tum");
  EXPECT_EQ(read.trackers[0].bodies, (std::vector<std::string>{"cam", "obj"}));
  EXPECT_EQ(read.extra, manifest.extra);
  ASSERT_EQ(read.clock_fits.count("kinect1"), 1u);
  EXPECT_EQ(read.clock_fits.at("kinect1").offset_ns, fit.offset_ns);
  EXPECT_EQ(read.clock_fits.at("kinect1").ns_per_tick, fit.ns_per_tick);
  EXPECT_EQ(read.clock_fits.at("kinect1").inliers, 297);
  EXPECT_FALSE(read.created_utc.empty());

  ASSERT_EQ(reader.frame_count("kinect1"), 5);
  for (int i = 0; i < 5; ++i) {
    const auto& entry = reader.frame("kinect1", i);
    EXPECT_EQ(entry.record.frame, i);
    EXPECT_EQ(entry.record.stamp_ns, 5'000'000'000 + 33'333'333LL * i);
    EXPECT_TRUE(entry.color_present && entry.depth_present);
    const cv::Mat color = reader.LoadColor("kinect1", i);
    EXPECT_EQ(cv::norm(color, TestColor(i), cv::NORM_INF), 0.0);  // PNG is lossless
    const DepthImage depth = reader.LoadDepth("kinect1", i);
    const cv::Mat raw = TestDepth(i);
    EXPECT_EQ(depth.at(0, 0), static_cast<float>(raw.at<uint16_t>(0, 0) * 0.001));
    EXPECT_EQ(depth.at(639, 479), static_cast<float>(raw.at<uint16_t>(479, 639) * 0.001));
    EXPECT_EQ(depth.at(120, 70), 0.0f);
  }
  ASSERT_EQ(reader.frame_count("tum"), 2);
  EXPECT_TRUE(reader.frame("tum", 0).record.has_color());
  EXPECT_FALSE(reader.frame("tum", 0).record.has_depth());
  EXPECT_EQ(reader.frame("tum", 0).record.source_id, "1305031102.175304");
  EXPECT_FALSE(reader.frame("tum", 1).record.has_color());
  const DepthImage tum_depth = reader.LoadDepth("tum", 1);
  EXPECT_FLOAT_EQ(tum_depth.at(10, 10), static_cast<float>(TestDepth(3).at<uint16_t>(10, 10) / 5000.0));
  EXPECT_THROW(reader.LoadDepth("tum", 0), InputError);

  const auto records = reader.tracker_records("ndi");
  ASSERT_EQ(records.size(), written.size());
  for (size_t i = 0; i < written.size(); ++i) ExpectSameRecord(records[i], written[i]);
  EXPECT_EQ(reader.PoseSamples("ndi", "cam").size(), 5u);
  EXPECT_EQ(reader.PoseSamples("ndi", "cam")[3].status, PoseStatus::kMissing);
  ASSERT_EQ(reader.tracker_records("known").size(), 1u);
  ASSERT_EQ(reader.events().size(), 1u);
  EXPECT_EQ(reader.events()[0].kind, "reconnect");
  EXPECT_EQ(reader.events()[0].detail, "port 2 came back");
  for (const auto& diagnostics : reader.diagnostics()) EXPECT_FALSE(diagnostics.torn_tail) << diagnostics.file;
}

TEST(SessionRoundTrip, JpegColourAndExrDepth) {
  TempDir tmp;
  SessionWriterOptions options;
  options.color_encoding = ColorEncoding::kJpeg;
  options.depth_encoding = DepthEncoding::kExr;
  cv::Mat metres(48, 64, CV_32FC1);
  cv::randu(metres, 0.4, 4.5);
  metres.at<float>(5, 7) = 0.0f;
  {
    auto writer = SessionWriter::Create(tmp.path() / "S", TwoCameraManifest(), options);
    writer->WriteCameraFrame("kinect1", {0, 0, 0, "", "", ""}, TestColor(1, 64, 48), metres);
  }
  const SessionReader reader = SessionReader::Open(tmp.path() / "S");
  EXPECT_EQ(reader.frame("kinect1", 0).record.color_file, "color/000000.jpg");
  EXPECT_EQ(reader.frame("kinect1", 0).record.depth_file, "depth/000000.exr");
  const cv::Mat color = reader.LoadColor("kinect1", 0);
  EXPECT_LT(cv::norm(color, TestColor(1, 64, 48), cv::NORM_L1) / color.total() / 3, 6.0);  // JPEG q95
  const DepthImage depth = reader.LoadDepth("kinect1", 0);
  ASSERT_EQ(depth.width, 64);
  for (int v = 0; v < 48; ++v)
    for (int u = 0; u < 64; ++u) ASSERT_EQ(depth.at(u, v), metres.at<float>(v, u));  // float EXR is exact
}

TEST(SessionRoundTrip, TumDepthUnitIsExact) {
  // Every 16-bit TUM value converts as the TUM tools do (value / 5000) to the same float.
  TempDir tmp;
  cv::Mat raw(256, 256, CV_16UC1);
  for (int i = 0; i < 65536; ++i) raw.at<uint16_t>(i / 256, i % 256) = static_cast<uint16_t>(i);
  {
    auto writer = SessionWriter::Create(tmp.path() / "S", TwoCameraManifest());
    writer->WriteCameraFrame("tum", {0, 0, 0, "", "", ""}, cv::Mat(), raw);
  }
  const DepthImage depth = SessionReader::Open(tmp.path() / "S").LoadDepth("tum", 0);
  int differing = 0;
  for (int i = 0; i < 65536; ++i)
    differing += depth.at(i % 256, i / 256) != static_cast<float>(i / 5000.0);
  EXPECT_EQ(differing, 0);
}

// The depth step the validator's accept floor takes (kinect.md section 8): the Kinect v1's disparity
// step grows as the square of the range; other cameras report one unit of their depth images.
TEST(CameraStreamInfo, DepthStepFollowsTheSensor) {
  CameraStreamInfo kinect1;
  kinect1.model = "kinect1";
  EXPECT_NEAR(kinect1.depth_step_m(1.0), 2.85e-3, 1e-12);
  EXPECT_NEAR(kinect1.depth_step_m(2.2), 13.8e-3, 0.05e-3);
  CameraStreamInfo kinect2;
  kinect2.model = "kinect2";
  EXPECT_DOUBLE_EQ(kinect2.depth_step_m(2.2), 0.001);
  CameraStreamInfo tum;
  tum.model = "tum";
  tum.depth_unit_m = 1.0 / 5000;
  EXPECT_DOUBLE_EQ(tum.depth_step_m(1.0), 0.0002);
}

TEST(SessionRoundTrip, ImportedFilesAreLinkedNotReencoded) {
  // Real TUM fr1/desk files registered as they are; a listed source that does not exist stays listed.
  namespace fs = std::filesystem;
  const fs::path root = fs::path(MOCAP_SHARED_DIR) / "realdata/tum_fr1_desk_9frames";
  const fs::path rgb = root / "rgb/1305031453.359684.png", depth = root / "depth/1305031453.374112.png";
  ASSERT_TRUE(fs::exists(rgb) && fs::exists(depth)) << "missing ../shared/realdata";
  TempDir tmp;
  {
    auto writer = SessionWriter::Create(tmp.path() / "S", TwoCameraManifest());
    writer->AddCameraFrameFiles("tum", {0, 0, 1'305'031'453'359'684'000, "1305031453.359684", "", ""}, rgb, depth);
    writer->AddCameraFrameFiles("tum", {1, 0, 1'305'031'453'395'000'000, "1305031453.395000", "", ""},
                                root / "rgb/1305031453.395000.png", fs::path());
    EXPECT_THROW(writer->AddCameraFrameFiles("tum", {}, root / "rgb.txt", fs::path()), InputError);
  }
  const SessionReader reader = SessionReader::Open(tmp.path() / "S");
  ASSERT_EQ(reader.frame_count("tum"), 2);
  EXPECT_TRUE(reader.frame("tum", 0).color_present && reader.frame("tum", 0).depth_present);
  EXPECT_EQ(fs::file_size(reader.ColorPath("tum", 0)), fs::file_size(rgb));  // the same bytes
  const cv::Mat original = cv::imread(depth.string(), cv::IMREAD_UNCHANGED);
  const DepthImage depth_m = reader.LoadDepth("tum", 0);
  for (int v = 0; v < 480; v += 37)
    for (int u = 0; u < 640; u += 41)
      ASSERT_EQ(depth_m.at(u, v), static_cast<float>(original.at<uint16_t>(v, u) / 5000.0));
  EXPECT_EQ(reader.frame("tum", 1).record.color_file, "color/000001.png");
  EXPECT_TRUE(reader.frame("tum", 1).record.has_color());
  EXPECT_FALSE(reader.frame("tum", 1).color_present);  // listed in rgb.txt, absent from the excerpt
  EXPECT_FALSE(reader.frame("tum", 1).record.has_depth());
}

TEST(SessionRoundTrip, CreateRefusesNonEmptyFolder) {
  TempDir tmp;
  std::filesystem::create_directories(tmp.path() / "S" / "x");
  EXPECT_THROW(SessionWriter::Create(tmp.path() / "S", TwoCameraManifest()), InputError);
}

TEST(SessionRoundTrip, UnknownStreamsAndBodiesAreRefused) {
  TempDir tmp;
  auto writer = SessionWriter::Create(tmp.path() / "S", TwoCameraManifest());
  EXPECT_THROW(writer->WriteTrackerSample("ndi", Sample("nobody", 0)), InputError);
  EXPECT_THROW(writer->WriteTrackerSample("nope", Sample("cam", 0)), InputError);
  EXPECT_THROW(writer->WriteCameraFrame("nope", {}, TestColor(0, 8, 8), cv::Mat()), InputError);
  EXPECT_THROW(writer->WriteCameraFrame("kinect1", {}, cv::Mat(), cv::Mat()), InputError);
}

TEST(SessionRoundTrip, CrashedWriterReadsAsIncomplete) {
  TempDir tmp;
  SessionManifest manifest = TwoCameraManifest();
  // A writer that never closes: emulate with the manifest it writes at Create.
  {
    auto writer = SessionWriter::Create(tmp.path() / "S", manifest);
    writer->WriteEvent({1, "note", "", "x"});
    EXPECT_FALSE(SessionReader::Open(tmp.path() / "S").complete());
  }
  EXPECT_TRUE(SessionReader::Open(tmp.path() / "S").complete());
}

}  // namespace
}  // namespace mocap
