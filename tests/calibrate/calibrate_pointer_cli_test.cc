// The NDI way to an object mount, end to end on simulated sessions: a tracked pointer (its own body,
// tip at its mesh's origin) pivoting in a divot (`calibrate pivot`), then resting on five landmarks of
// the engine block after lying on the table (`calibrate object-mount --pointer --landmarks`); both
// compared with the truth the simulator used (S/truth/calibration.json). Bad input: one clear line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/rigid3.h"
#include "pipeline/object_library.h"
#include "cli_run.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::LastJson;
using test::Mocaplabel;
using test::PoseOf;
using test::ReadText;
using test::TruthPoseOf;

// Where the pointer's tip (its mesh origin) sits in its body's frame: 175 mm below the markers.
const Rigid3d kT_pointerbody_tip(Eigen::Quaterniond(Eigen::AngleAxisd(0.035, Eigen::Vector3d::UnitX())),
                                 Eigen::Vector3d(0.012, 0.021, -0.175));
// Landmarks of the engine block (mesh frame, mm): plug bosses, crank pulley, oil filter, bell housing.
const std::vector<Eigen::Vector3d> kLandmarksMm = {{-135, 0, 305}, {135, 0, 305}, {227, 0, 105}, {60, -228, 110}, {-235, 0, 250}};
const Eigen::Vector3d kDivot(0.0, -0.25, 0.77);

Rigid3d Rpy(const Eigen::Vector3d& xyz, double roll, double pitch, double yaw) {
  const double d = M_PI / 180;
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(yaw * d, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch * d, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(roll * d, Eigen::Vector3d::UnitX())),
                 xyz);
}

std::string Keyframe(double t_s, const Rigid3d& T) {
  const Eigen::Vector3d p = T.translation(), ypr = T.rotation().toRotationMatrix().eulerAngles(2, 1, 0) * 180 / M_PI;
  std::ostringstream out;
  out.precision(10);
  out << "      - {t_s: " << t_s << ", translation_m: [" << p.x() << ", " << p.y() << ", " << p.z() << "], rpy_deg: [" << ypr(2)
      << ", " << ypr(1) << ", " << ypr(0) << "]}\n";
  return out.str();
}

/// The default scene (robot-head camera) at 2 Hz with the table, the engine block, and the pointer moving through `pointer_keyframes`.
std::string Scenario(double duration_s, const std::string& pointer_keyframes) {
  std::string text = ReadText(fs::path(MOCAP_SOURCE_DIR) / "scenarios/default.yaml");
  text = std::regex_replace(text, std::regex("frame_rate_hz: [0-9]+"), "frame_rate_hz: 2");
  text = std::regex_replace(text, std::regex("frame_count: [0-9]+"), "frame_count: " + std::to_string(static_cast<int>(2 * duration_s)));
  return text.substr(0, text.find("objects:\n")) +
         "objects:\n  - name: table\n    keyframes: [{t_s: 0, translation_m: [0, 0, 0]}]\n"
         "  - name: engine_block\n    keyframes: [{t_s: 0, translation_m: [-0.25, 0.05, 0.75], rpy_deg: [0, 0, 90]}]\n"
         "  - name: pointer\n    keyframes:\n" + pointer_keyframes + "occluders: []\n";
}

/// Turning about the tip in the divot for 10 s, after being lowered into it.
std::string PivotKeyframes() {
  std::string k = Keyframe(0, Rpy(kDivot + Eigen::Vector3d(0, 0, 0.06), 0, 0, 0)) + Keyframe(0.8, Rpy(kDivot, 0, 0, 0));
  for (int i = 1; i <= 20; ++i)
    k += Keyframe(0.8 + 0.5 * i, Rpy(kDivot, 25 * std::sin(2 * M_PI * i / 7), 25 * std::cos(2 * M_PI * i / 5), 15 * std::sin(i)));
  return k;
}

/// Lying still on the table, then 1 s of travel and 1 s of rest on each landmark, then back.
std::string TouchKeyframes(const Rigid3d& T_world_mesh) {
  const Rigid3d parked = Rpy({0.1, -0.3, 0.8}, 0, -30, 0);  // leaning on something, markers towards the tracker
  std::string k = Keyframe(0, parked) + Keyframe(1, parked);
  double t = 1;
  for (size_t i = 0; i < kLandmarksMm.size(); ++i) {
    const Rigid3d at = Rpy(T_world_mesh * (kLandmarksMm[i] / 1000.0), 10.0 * (i % 3 - 1.0), 12.0 * ((i + 1) % 3 - 1.0), 30.0 * i);
    k += Keyframe(t + 1, at) + Keyframe(t + 2, at);
    t += 2;
  }
  return k + Keyframe(t + 1, parked) + Keyframe(t + 3, parked);
}

struct PointerSetup {
  fs::path dir, objects;
};

/// The built-in library with the pointer added (a thin pyramid, tip at its origin, along +z).
PointerSetup Library(const std::string& name) {
  PointerSetup s;
  s.dir = fs::temp_directory_path() / ("mocaplabel_pointer_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(s.dir);
  std::string out;
  EXPECT_EQ(Mocaplabel({"sim", "meshes", "--out", (s.dir / "lib").string()}, &out), 0) << out;
  std::ofstream(s.dir / "lib" / "pointer.obj") << "v 0 0 0\nv 0.006 0.006 0.18\nv -0.006 0.006 0.18\nv -0.006 -0.006 0.18\n"
                                                  "v 0.006 -0.006 0.18\nf 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 2\nf 2 5 4\nf 2 4 3\n";
  pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(s.dir / "lib" / "objects.yaml");
  pipeline::LibraryObject pointer;
  pointer.id = 91, pointer.name = "pointer", pointer.object_class = "pointer";
  pointer.mesh = "pointer.obj", pointer.mesh_path = s.dir / "lib" / "pointer.obj";
  pointer.mounts.push_back({"pointer_body", kT_pointerbody_tip});
  pointer.markers = pipeline::ObjectMarkers{{{0, 0, 0}, {0.05, 0, 0}, {0.015, 0.06, 0}, {-0.03, 0.035, 0}}, Eigen::Vector3d::UnitZ()};
  library.objects.push_back(pointer);
  s.objects = s.dir / "lib" / "objects.yaml";
  pipeline::WriteObjectLibrary(library, s.objects);
  return s;
}

fs::path Record(const PointerSetup& s, const std::string& name, double duration_s, const std::string& keyframes) {
  std::ofstream(s.dir / (name + ".yaml")) << Scenario(duration_s, keyframes);
  std::string out;
  EXPECT_EQ(Mocaplabel({"sim", "record", "--scenario", (s.dir / (name + ".yaml")).string(), "--objects", s.objects.string(), "--out",
                        (s.dir / name).string(), "--progress", "none"}, &out), 0) << out;
  return s.dir / name;
}

std::string LandmarksYaml(size_t count) {
  std::ostringstream out;
  out << "unit: mm\nlandmarks:\n";
  const char* names[] = {"plug_1", "plug_4", "crank_pulley", "oil_filter", "bell_housing"};
  for (size_t i = 0; i < count; ++i)
    out << "  - {name: " << names[i] << ", mesh: [" << kLandmarksMm[i].x() << ", " << kLandmarksMm[i].y() << ", " << kLandmarksMm[i].z() << "]}\n";
  return out.str();
}

TEST(CalibratePointerCli, PivotThenLandmarksGiveTheObjectMount) {
  const PointerSetup s = Library("mount");
  const fs::path pivot = Record(s, "pivot", 12, PivotKeyframes());
  std::string out;
  ASSERT_EQ(Mocaplabel({"calibrate", "pivot", pivot.string(), "--pointer-body", "pointer_body", "--out", (s.dir / "pointer.yaml").string(), "--json"}, &out), 0) << out;
  const json p = LastJson(out);
  const Eigen::Vector3d tip(p["tip_m"][0], p["tip_m"][1], p["tip_m"][2]);
  std::printf("pivot: tip %.3f mm from the truth, wobble %.3f mm RMS, %d poses (%d dropped)\n", 1e3 * (tip - kT_pointerbody_tip.translation()).norm(),
              p["rms_mm"].get<double>(), p["samples_used"].get<int>(), p["samples_dropped"].get<int>());
  EXPECT_LT(1e3 * (tip - kT_pointerbody_tip.translation()).norm(), 0.5);
  EXPECT_GT(p["samples_dropped"].get<int>(), 5);  // lowered into the divot: not pivoting
  EXPECT_NE(ReadText(s.dir / "pointer.yaml").find("pointer_body: pointer_body"), std::string::npos);

  // The engine block nearer the middle of the tracker's volume than in the default scene: the pointer's
  // markers stand 175 mm above the landmarks.
  const Rigid3d T_world_engine = Rpy({-0.25, 0.05, 0.75}, 0, 0, 90);
  const fs::path touch = Record(s, "touch", 14, TouchKeyframes(T_world_engine));
  std::ofstream(s.dir / "landmarks.yaml") << LandmarksYaml(kLandmarksMm.size());
  ASSERT_EQ(Mocaplabel({"calibrate", "object-mount", touch.string(), "--object", "engine_block", "--objects", s.objects.string(), "--pointer",
                        (s.dir / "pointer.yaml").string(), "--landmarks", (s.dir / "landmarks.yaml").string(), "--out",
                        (s.dir / "calibrated.yaml").string(), "--json"}, &out), 0) << out;
  const json m = LastJson(out);
  const json truth = json::parse(ReadText(touch / "truth" / "calibration.json"));
  const Rigid3d true_mount = TruthPoseOf(truth["true"]["T_objbody_mesh"]["engine_block"]);
  const Rigid3d found = PoseOf(m["T_body_mesh"]);
  std::printf("landmarks: mount %.3f mm / %.4f deg from the truth, registration %.3f mm RMS, %zu rests\n",
              1e3 * TranslationDistanceM(found, true_mount), RotationDistanceDeg(found, true_mount), m["fre_rms_mm"].get<double>(),
              m["rests"].get<size_t>());
  EXPECT_LT(1e3 * TranslationDistanceM(found, true_mount), 1.0);
  EXPECT_LT(RotationDistanceDeg(found, true_mount), 0.3);
  EXPECT_EQ(m["rests"].get<size_t>(), kLandmarksMm.size() + 2);  // parked before and after: not landmarks
  const pipeline::ObjectLibrary written = pipeline::ReadObjectLibrary(s.dir / "calibrated.yaml");
  EXPECT_LT(1e3 * TranslationDistanceM(written.Find("engine_block")->mounts.front().T_body_mesh, true_mount), 1.0);

  // Bad input: more landmarks than rests, landmarks touched in another order, a pointer file in mm.
  std::string bad = LandmarksYaml(kLandmarksMm.size()) + "  - {name: extra, mesh: [0, 0, 0]}\n";
  for (int i = 0; i < 2; ++i) bad += "  - {name: extra" + std::to_string(i) + ", mesh: [" + std::to_string(10 * i) + ", 50, 0]}\n";
  std::ofstream(s.dir / "more.yaml") << bad;
  EXPECT_NE(Mocaplabel({"calibrate", "object-mount", touch.string(), "--object", "engine_block", "--objects", s.objects.string(), "--pointer",
                        (s.dir / "pointer.yaml").string(), "--landmarks", (s.dir / "more.yaml").string()}, &out), 0);
  EXPECT_NE(out.find("rested 7 times for 8 landmarks"), std::string::npos) << out;
  std::string swapped = LandmarksYaml(kLandmarksMm.size());
  swapped = std::regex_replace(swapped, std::regex("name: plug_4, mesh: \\[135"), "name: plug_4, mesh: [-135");
  swapped = std::regex_replace(swapped, std::regex("name: plug_1, mesh: \\[-135"), "name: plug_1, mesh: [135");
  swapped = std::regex_replace(swapped, std::regex("\\[60, -228"), "[60, 228");
  std::ofstream(s.dir / "swapped.yaml") << swapped;
  EXPECT_NE(Mocaplabel({"calibrate", "object-mount", touch.string(), "--object", "engine_block", "--objects", s.objects.string(), "--pointer",
                        (s.dir / "pointer.yaml").string(), "--landmarks", (s.dir / "swapped.yaml").string()}, &out), 0);
  EXPECT_NE(out.find("is as far apart as the landmarks"), std::string::npos) << out;
  std::ofstream(s.dir / "mm.yaml") << "pointer_body: pointer_body\ntip_m: [12, 21, -175]\n";
  EXPECT_NE(Mocaplabel({"calibrate", "object-mount", touch.string(), "--object", "engine_block", "--objects", s.objects.string(), "--pointer",
                        (s.dir / "mm.yaml").string(), "--landmarks", (s.dir / "landmarks.yaml").string()}, &out), 0);
  EXPECT_NE(out.find("mm.yaml:2"), std::string::npos) << out;
  EXPECT_NE(Mocaplabel({"calibrate", "pivot", touch.string(), "--pointer-body", "no_such_body"}, &out), 0);
  EXPECT_NE(out.find("no tracker of the session reports body 'no_such_body'"), std::string::npos) << out;
  fs::remove_all(s.dir);
}

}  // namespace
}  // namespace mocap
