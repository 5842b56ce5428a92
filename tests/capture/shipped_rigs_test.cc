// The rig files shipped in calib/ pass the strict reader, and the emulator rig fits the tour of
// docs/capture.md: its bodies are the labeller's (cameras[].body, meshes/objects.yaml tracker bodies),
// its tracker is a replay, and its control port is any free one. Also the capture: keys the tour needs.
#include <gtest/gtest.h>

#include <set>

#include "core/check.h"
#include "pipeline/object_library.h"
#include "pipeline/rig.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> ShippedRigs() {
  std::vector<fs::path> rigs;
  for (const fs::directory_entry& entry : fs::directory_iterator(fs::path(MOCAP_SOURCE_DIR) / "calib"))
    if (entry.path().extension() == ".yaml") rigs.push_back(entry.path());
  return rigs;
}

TEST(ShippedRigs, EveryCalibRigPassesTheStrictReader) {
  const std::vector<fs::path> rigs = ShippedRigs();
  EXPECT_GE(rigs.size(), 2u) << "calib/example_rig.yaml and calib/emulator_rig.yaml";
  for (const fs::path& rig : rigs) {
    try {
      pipeline::ReadRig(rig);
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
}

TEST(ShippedRigs, EmulatorRigServesTheLabellersBodies) {
  const pipeline::Rig rig = pipeline::ReadRig(fs::path(MOCAP_SOURCE_DIR) / "calib" / "emulator_rig.yaml");
  const pipeline::CaptureOptions capture = pipeline::CaptureOptionsOf(rig);
  ASSERT_TRUE(capture.tracker && capture.cameras.size() == 1);
  EXPECT_TRUE(capture.tracker->replay);
  EXPECT_EQ(capture.control.port, 0);
  EXPECT_EQ(std::get<capture::Kinect1SourceOptions>(capture.cameras[0]).camera_body, "camera_body") << "the camera's calibration goes into the manifest";
  std::set<std::string> tools;
  for (const ndi::ToolSpec& tool : capture.tracker->client.tools) tools.insert(tool.name);
  ASSERT_EQ(rig.cameras.size(), 1u);
  EXPECT_TRUE(tools.count(*rig.cameras[0].body)) << "the camera body is a tracker tool";
  const pipeline::ObjectLibrary objects = pipeline::ReadObjectLibrary(fs::path(MOCAP_SOURCE_DIR) / "meshes" / "objects.yaml");
  for (const pipeline::LibraryObject& object : objects.objects)
    for (const BodyMount& mount : object.mounts) EXPECT_TRUE(tools.count(mount.body)) << object.name << ": " << mount.body;
  EXPECT_EQ(tools.size(), capture.tracker->client.tools.size()) << "a tool listed twice";
}

TEST(ShippedRigs, CaptureReplayFlagIsReadStrictly) {
  const std::string rig = "capture:\n  tracker: {tcp: \"127.0.0.1:1\", replay: true}\n  control: {port: 0}\n";
  const pipeline::CaptureOptions capture = pipeline::CaptureOptionsOf(pipeline::ParseRig(rig, "rig.yaml"));
  EXPECT_TRUE(capture.tracker->replay);
  EXPECT_EQ(capture.control.port, 0);
  EXPECT_FALSE(pipeline::CaptureOptionsOf(pipeline::ParseRig("capture:\n  tracker: {tcp: \"h:1\"}\n", "r.yaml")).tracker->replay);
  try {
    pipeline::ParseRig("capture:\n  tracker: {tcp: \"h:1\", replya: true}\n", "r.yaml");
    FAIL() << "a misspelt key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'replay'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pipeline::ParseRig("capture:\n  tracker: {tcp: \"h:1\", replay: maybe}\n", "r.yaml"), InputError);
}

std::string CaptureRigError(const std::string& capture) {
  try {
    pipeline::ParseRig("capture:\n" + capture, "rig.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

// Several cameras: a list under cameras: (kinect1 and kinect2), each with the rig's calibration, written
// back as read; names unique across the streams, camera: and cameras: not both, keys per model.
TEST(CaptureRig, ListsSeveralCameras) {
  const std::string text =
      "cameras:\n  - {name: front, body: front_body}\n"
      "capture:\n  cameras:\n    - {name: front, model: kinect1, index: 1}\n"
      "    - {name: side, model: kinect2, serial: \"012345\", pipeline: cpu}\n";
  const pipeline::Rig rig = pipeline::ParseRig(text, "rig.yaml");
  const pipeline::CaptureOptions capture = pipeline::CaptureOptionsOf(rig);
  ASSERT_EQ(capture.cameras.size(), 2u);
  EXPECT_EQ(std::get<capture::Kinect1SourceOptions>(capture.cameras[0]).camera_body, "front_body");
  EXPECT_EQ(std::get<capture::Kinect1SourceOptions>(capture.cameras[0]).device.device_index, 1);
  const auto& side = std::get<capture::Kinect2SourceOptions>(capture.cameras[1]);
  EXPECT_EQ(side.stream, "side");
  EXPECT_EQ(side.device.serial, "012345");
  EXPECT_EQ(side.device.pipeline, "cpu");
  const pipeline::Rig again = pipeline::ParseRig(pipeline::EmitRig(rig), "again.yaml");
  ASSERT_EQ(again.capture->cameras.size(), 2u);
  EXPECT_EQ(std::get<capture::Kinect2SourceOptions>(again.capture->cameras[1]).device.serial, "012345");

  EXPECT_NE(CaptureRigError("  cameras:\n    - {name: a}\n    - {name: a, model: kinect2}\n").find("'a' is used twice"), std::string::npos);
  EXPECT_NE(CaptureRigError("  camera: {name: a}\n  cameras:\n    - {name: b}\n").find("not both"), std::string::npos);
  EXPECT_NE(CaptureRigError("  cameras:\n    - {name: a, model: kinect3}\n").find("drives kinect1 and kinect2"), std::string::npos);
  EXPECT_NE(CaptureRigError("  cameras:\n    - {name: a, model: kinect2, index: 0}\n").find("by serial"), std::string::npos);
  const std::string typo = CaptureRigError("  cameras:\n    - {name: a, seriall: x}\n");
  EXPECT_NE(typo.find("rig.yaml:3"), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean 'serial'"), std::string::npos) << typo;
}

// A Kinect2 in a build without libfreenect2 fails at Open, saying why (the daemon then stops at start).
TEST(CaptureRig, Kinect2SourceWithoutLibfreenect2SaysWhy) {
  if (capture::Kinect2SupportBuilt()) GTEST_SKIP() << "this build has libfreenect2";
  auto source = capture::CreateCameraSource(capture::Kinect2SourceOptions{});
  try {
    source->Open();
    FAIL() << "opened a Kinect2 without libfreenect2";
  } catch (const capture::DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("libfreenect2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mocap
