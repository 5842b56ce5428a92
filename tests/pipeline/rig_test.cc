// The rig (pipeline/rig.h): its strict reader (the errors name file:line and the key), its writer, the
// labeller's view and the capture daemon's options.
#include "pipeline/rig.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>

#include "core/check.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

const std::string kRig = R"(name: lab
tracker_latency_ms: 2.5
cameras:
  - name: kinect1
    body: camera_body
    T_body_camera:
      translation_m: [0.012, -0.045, 0.031]
      rotation_wxyz: [1, 0, 0, 0]
    intrinsics: {width: 640, height: 480, fx: 517.3, fy: 516.5, cx: 318.6, cy: 255.3, dist: [0.26, -0.95, 0, 0, 1.16]}
)";

std::string RigError(const std::string& text) {
  try {
    pipeline::ParseRig(text, "rig.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(Rig, StrictReaderNamesFileLineAndKey) {
  EXPECT_EQ(RigError(kRig), "");
  // The typo re-labelling exists to catch: a misspelt mount would silently keep the session's.
  const std::string typo = RigError(Replace(kRig, "T_body_camera:", "T_body_camra:"));
  EXPECT_NE(typo.find("rig.yaml:6"), std::string::npos) << typo;
  EXPECT_NE(typo.find("unknown key 'T_body_camra'"), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean 'T_body_camera'"), std::string::npos) << typo;
  // A wrong type.
  const std::string type = RigError(Replace(kRig, "fx: 517.3", "fx: wide"));
  EXPECT_NE(type.find("rig.yaml:9"), std::string::npos) << type;
  EXPECT_NE(type.find("'fx'"), std::string::npos) << type;
  // A rotation that is not a rotation (an xyzw quaternion would pass; a typo does not).
  const std::string rotation = RigError(Replace(kRig, "rotation_wxyz: [1, 0, 0, 0]", "rotation_wxyz: [1, 0, 0.5, 0]"));
  EXPECT_NE(rotation.find("rig.yaml:8"), std::string::npos) << rotation;
  EXPECT_NE(rotation.find("not a rotation"), std::string::npos) << rotation;
  // A unit that is not a unit: the latency in seconds under a millisecond key, or with its unit written.
  const std::string unit = RigError(Replace(kRig, "tracker_latency_ms: 2.5", "tracker_latency_ms: 2.5 ms"));
  EXPECT_NE(unit.find("rig.yaml:2"), std::string::npos) << unit;
  EXPECT_NE(unit.find("'tracker_latency_ms'"), std::string::npos) << unit;
  const std::string seconds = RigError(Replace(kRig, "tracker_latency_ms: 2.5", "tracker_latency_s: 0.0025"));
  EXPECT_NE(seconds.find("did you mean 'tracker_latency_ms'"), std::string::npos) << seconds;
  // Structure and values.
  EXPECT_NE(RigError(Replace(kRig, "width: 640", "width: -640")).find("rig.yaml:9"), std::string::npos);
  EXPECT_NE(RigError(kRig + "  - name: kinect1\n").find("appears twice"), std::string::npos);
  EXPECT_NE(RigError(kRig + "capture:\n  sessions_dir: s\n").find("neither a tracker nor a camera"), std::string::npos);
  EXPECT_NE(RigError(kRig + "capture:\n  tracker: {tcp: 'host:80x'}\n").find("rig.yaml:11"), std::string::npos);
}

TEST(Rig, WrittenAndReadBackIsTheSameRig) {
  const std::string text = kRig + "capture:\n  sessions_dir: sessions\n  control: {bind: 127.0.0.1, port: 8790}\n"
                                  "  tracker: {name: ndi, tcp: '10.0.0.5:8765', rate_hz: 60, replay: true, tools: [{name: wand, rom: w.rom}]}\n"
                                  "  camera: {name: kinect1, index: 1}\n";
  const pipeline::Rig rig = pipeline::ParseRig(text, "rig.yaml");
  const std::string emitted = pipeline::EmitRig(rig);
  const pipeline::Rig again = pipeline::ParseRig(emitted, "again.yaml");
  EXPECT_EQ(pipeline::EmitRig(again), emitted);
  EXPECT_EQ(again.tracker_latency_ns, 2'500'000);
  EXPECT_EQ(again.cameras[0].intrinsics->dist[4], 1.16);
  EXPECT_EQ(again.cameras[0].T_body_camera->translation(), rig.cameras[0].T_body_camera->translation());
  ASSERT_TRUE(again.capture.has_value());
  EXPECT_EQ(again.capture->control.port, 8790);
  EXPECT_EQ(again.capture->tracker->client.host, "10.0.0.5");
  EXPECT_EQ(again.capture->tracker->client.tools.at(0).rom_path, "w.rom");
  EXPECT_TRUE(again.capture->tracker->replay);
  EXPECT_EQ(std::get<capture::Kinect1SourceOptions>(again.capture->cameras.at(0)).device.device_index, 1);
}

TEST(Rig, ADepthToColourExtrinsicReadsWritesAndReachesTheLabellersView) {
  const std::string text = kRig + "  - name: kinect2\n    T_color_depth: {translation_m: [0.052, 0.001, -0.002], rotation_wxyz: [1, 0, 0, 0]}\n";
  const pipeline::Rig rig = pipeline::ParseRig(text, "rig.yaml");
  ASSERT_TRUE(rig.Find("kinect2")->T_color_depth.has_value());
  EXPECT_FALSE(rig.Find("kinect1")->T_color_depth.has_value());
  const pipeline::Rig again = pipeline::ParseRig(pipeline::EmitRig(rig), "again.yaml");
  EXPECT_EQ(again.Find("kinect2")->T_color_depth->translation(), Eigen::Vector3d(0.052, 0.001, -0.002));
  EXPECT_EQ(pipeline::LabelRigOf(again).Find("kinect2")->T_color_depth->translation().x(), 0.052);
  EXPECT_NE(RigError(Replace(text, "T_color_depth", "T_colour_depth")).find("unknown key 'T_colour_depth'"), std::string::npos);
}

TEST(Rig, ViewsCarryTheCalibration) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_rig_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "rig.yaml") << kRig << "capture:\n  camera: {name: kinect1}\n";
  const pipeline::Rig rig = pipeline::ReadRig(dir / "rig.yaml");
  const LabelRig label = pipeline::LabelRigOf(rig);
  EXPECT_EQ(label.tracker_latency_ns, 2'500'000);
  EXPECT_EQ(*label.Find("kinect1")->body, "camera_body");
  const pipeline::CaptureOptions capture = pipeline::CaptureOptionsOf(rig);
  EXPECT_EQ(capture.daemon.sessions_dir, dir / "sessions");
  EXPECT_EQ(std::get<capture::Kinect1SourceOptions>(capture.cameras.at(0)).camera_body, "camera_body");
  EXPECT_EQ(std::get<capture::Kinect1SourceOptions>(capture.cameras.at(0)).color_camera->fx, 517.3);
  // The shipped example rig reads.
  EXPECT_NO_THROW(pipeline::ReadRig(fs::path(MOCAP_SOURCE_DIR) / "calib/example_rig.yaml"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mocap
