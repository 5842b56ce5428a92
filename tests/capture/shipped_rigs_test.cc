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
  ASSERT_TRUE(capture.tracker && capture.camera);
  EXPECT_TRUE(capture.tracker->replay);
  EXPECT_EQ(capture.control.port, 0);
  EXPECT_EQ(capture.camera->camera_body, "camera_body") << "the camera's calibration goes into the manifest";
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

}  // namespace
}  // namespace mocap
