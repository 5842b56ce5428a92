#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/scenario_yaml.h"
#include "core/check.h"
#include "sim/scene_motion.h"

namespace mocap::cli {
namespace {

std::string ReadText(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

/// The error message of parsing `text`, or "" when it parses.
std::string ParseError(const std::string& text) {
  try {
    ParseScenarioYaml(text, "scene.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioYaml, CommittedDefaultIsTheEmbeddedDefault) {
  const std::filesystem::path path = std::filesystem::path(MOCAP_SOURCE_DIR) / "scenarios" / "default.yaml";
  EXPECT_EQ(ReadText(path), EncodeScenarioYaml(sim::DefaultScenario()))
      << "regenerate with `mocaplabel sim check --print-yaml > scenarios/default.yaml`";
  const sim::Scenario parsed = LoadScenarioYaml(path);
  const sim::Scenario embedded = sim::DefaultScenario();
  EXPECT_NO_THROW(parsed.check(sim::DefaultSimObjects(), path.string()));
  const sim::SceneMotion a(parsed), b(embedded);
  for (double t = 0; t <= 10.0; t += 0.37) {
    EXPECT_LT(TranslationDistanceM(a.T_world_camera(t), b.T_world_camera(t)), 1e-6);
    EXPECT_LT(RotationDistanceDeg(a.T_world_camera(t), b.T_world_camera(t)), 1e-5);
    for (size_t i = 0; i < embedded.objects.size(); ++i) {
      EXPECT_LT(TranslationDistanceM(a.T_world_mesh(i, t), b.T_world_mesh(i, t)), 1e-6);
      EXPECT_LT(RotationDistanceDeg(a.T_world_mesh(i, t), b.T_world_mesh(i, t)), 1e-5);
    }
    EXPECT_LT(TranslationDistanceM(a.T_world_occluder(0, t), b.T_world_occluder(0, t)), 1e-6);
  }
  EXPECT_LT(TranslationDistanceM(parsed.options.tracker.T_world_tracker, embedded.options.tracker.T_world_tracker), 1e-6);
  EXPECT_LT(RotationDistanceDeg(parsed.T_cambody_camera, embedded.T_cambody_camera), 1e-5);
  EXPECT_EQ(parsed.options.seed, embedded.options.seed);
}

TEST(ScenarioYaml, FieldsOverrideTheDefault) {
  const sim::Scenario s = ParseScenarioYaml(R"(
name: carry
frame_count: 90
sensor: kinect2
tracker:
  noise_rms_mm: 0.25
  pose: {look_at: {position: [0, 1, 2.5], target: [0, 0, 0.9]}}
errors:
  camera_mount: {translation_m: [0.005, 0, 0]}
  latency_ms: 20
camera:
  motion: handheld
  keyframes:
    - {t_s: 0, look_at: {position: [-0.8, 0.1, 1.3], target: [0, 0, 0.8]}}
    - {t_s: 3, translation_m: [-0.7, -0.2, 1.3], rpy_deg: [-120, 0, -80]}
  shake_mm: 2
objects:
  - name: funnel
    keyframes: [{t_s: 0, translation_m: [0, 0, 0.75]}]
occluders: []
)",
                                            "scene.yaml");
  EXPECT_EQ(s.options.name, "carry");
  EXPECT_EQ(s.options.frame_count, 90);
  EXPECT_EQ(s.options.sensor, sim::SensorKind::kKinect2);
  EXPECT_DOUBLE_EQ(s.options.tracker.noise_rms_mm, 0.25);
  EXPECT_DOUBLE_EQ(s.options.tracker.latency_ms, 14.2);  // default kept
  EXPECT_DOUBLE_EQ(s.options.errors.latency_ms, 20);
  EXPECT_EQ(s.camera.type, sim::CameraMotion::Type::kHandheld);
  EXPECT_EQ(s.camera.handheld.size(), 2u);
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_TRUE(s.occluders.empty());
  // The tracker looks at its target along its -z axis (NDI convention).
  const Eigen::Vector3d axis = s.options.tracker.T_world_tracker.rotation() * -Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.dot((Eigen::Vector3d(0, 0, 0.9) - Eigen::Vector3d(0, 1, 2.5)).normalized()), 1.0, 1e-12);
  EXPECT_NO_THROW(s.check(sim::DefaultSimObjects(), "scene.yaml"));
}

TEST(ScenarioYaml, BadInputNamesFileAndLine) {
  EXPECT_NE(ParseError("frame_count: 10\ntracker:\n  rate_hz: fast\n").find("scene.yaml:3"), std::string::npos);
  EXPECT_NE(ParseError("frame_count: 10\nframe_rat_hz: 30\n").find("scene.yaml:2"), std::string::npos);
  EXPECT_NE(ParseError("sensor: kinect3\n").find("kinect3"), std::string::npos);
  EXPECT_NE(ParseError("objects:\n  - name: funnel\n    keyframes:\n      - {t_s: 1, translation_m: [0, 0]}\n").find("scene.yaml:4"),
            std::string::npos);
  EXPECT_NE(ParseError("objects:\n  - name: funnel\n    keyframes:\n      - {t_s: 1, translation_m: [0, 0, 0]}\n"
                       "      - {t_s: 0.5, translation_m: [0, 0, 0]}\n")
                .find("scene.yaml:5"),
            std::string::npos);
  EXPECT_NE(ParseError("tracker: {pose: {translation_m: [0, 0, 0], rotation_wxyz: [2, 0, 0, 0]}}\n").find("norm"), std::string::npos);
  EXPECT_NE(ParseError("tracker: [1, 2\n").find("scene.yaml"), std::string::npos);
  EXPECT_NE(ParseError("tracker:\n  rate_hz: -5\n").find("rate_hz"), std::string::npos);
  EXPECT_EQ(ParseError("frame_count: 10\n"), "");
  EXPECT_THROW(LoadScenarioYaml("/nonexistent/scene.yaml"), InputError);
}

}  // namespace
}  // namespace mocap::cli

namespace mocap::cli {
namespace {

// Found by tests/fuzz (fuzz_yaml): names were written unquoted, so a name holding a newline or ": " (or one
// that reads as another type) made the written scenario unreadable.
TEST(ScenarioYaml, AnyNameIsWrittenSoThatItReadsBack) {
  sim::Scenario s = sim::DefaultScenario();
  s.options.name = "handheld-kine\namect: \"x\" \\ \t #y";
  s.camera_body.name = "true";
  s.objects.at(0).name = "- [a, {b}]";
  s.occluders.at(0).mesh = "box, with: comma";
  s.options.errors.object_mounts.push_back({"{x}: y", Eigen::Vector3d(0.001, 0, 0), Eigen::Vector3d::Zero()});
  const std::string written = EncodeScenarioYaml(s);
  const sim::Scenario read = ParseScenarioYaml(written, "written.yaml");
  EXPECT_EQ(read.options.name, s.options.name);
  EXPECT_EQ(read.camera_body.name, "true");
  EXPECT_EQ(read.objects.at(0).name, s.objects.at(0).name);
  EXPECT_EQ(read.occluders.at(0).mesh, s.occluders.at(0).mesh);
  EXPECT_EQ(read.options.errors.object_mounts.at(0).object, "{x}: y");
  EXPECT_EQ(EncodeScenarioYaml(read), written);
}

TEST(ScenarioYaml, DepthLossReadsBackAndIsChecked) {
  sim::Scenario s = sim::DefaultScenario();
  s.objects.at(2).depth_loss = 0.5;
  s.occluders.at(0).depth_loss = 0.25;
  const sim::Scenario read = ParseScenarioYaml(EncodeScenarioYaml(s), "written.yaml");
  EXPECT_EQ(read.objects.at(2).depth_loss, 0.5);
  EXPECT_EQ(read.objects.at(1).depth_loss, 0.0);
  EXPECT_EQ(read.occluders.at(0).depth_loss, 0.25);
  s.objects.at(2).depth_loss = 1.5;
  EXPECT_THROW(ParseScenarioYaml(EncodeScenarioYaml(s), "written.yaml"), InputError);
}

TEST(ScenarioYaml, TheExampleInTheDocsIsValid) {
  const std::string doc = ReadText(std::filesystem::path(MOCAP_SOURCE_DIR) / "docs" / "simulation.md");
  const size_t begin = doc.find("```yaml\n");
  ASSERT_NE(begin, std::string::npos);
  const size_t end = doc.find("```", begin + 8);
  const sim::Scenario s = ParseScenarioYaml(doc.substr(begin + 8, end - begin - 8), "docs/simulation.md");
  EXPECT_NO_THROW(s.check(sim::DefaultSimObjects(), "docs/simulation.md"));
  EXPECT_EQ(s.options.sensor, sim::SensorKind::kKinect2);
  EXPECT_TRUE(s.options.errors.any());
  EXPECT_EQ(s.objects.size(), 3u);
}

}  // namespace
}  // namespace mocap::cli
