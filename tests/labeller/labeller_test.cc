#include "label/labeller.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <map>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/pipeline/label_run_testing.h"
#include "core/check.h"
#include "labeller_test_util.h"

namespace mocap {
namespace {

using testing::FreshDir;
using testing::kMs;
using testing::ReadJsonLines;

const Eigen::Vector3d kMarker_mesh(0.03, -0.02, 0.0);

LabelObject MarkerObject(const std::filesystem::path& dir, const testing::SyntheticRig& rig) {
  testing::WriteMarkerSquareObj(dir / "marker.obj", kMarker_mesh, 1.0);
  return {.id = 7, .name = "marker", .object_class = "marker", .mesh_path = dir / "marker.obj",
          .unit_scale_to_m = 1.0, .mounts = {{rig.objbody, rig.T_objbody_mesh}}};
}

LabelRunOptions Options(const std::filesystem::path& out) {
  LabelRunOptions options;
  options.out_dir = out;
  options.threads = 2;
  options.output.write_overlay = true;
  return options;
}

TEST(Labeller, BackFaceCullingPerObject) {
  // The marker object is an open square: kAuto keeps its back faces, objects.yaml may force culling,
  // and the manifest says which was done and why.
  const auto dir = FreshDir("culling");
  const testing::SyntheticRig rig;
  rig.WriteSession(dir / "S", 1);
  std::vector<LabelObject> objects = {MarkerObject(dir, rig)};
  const LabelSummary automatic = LabelSession(SessionReader::Open(dir / "S"), objects, LabelRig{}, Options(dir / "L"));
  ASSERT_EQ(automatic.culling.size(), 1u);
  EXPECT_FALSE(automatic.culling[0].culled);
  EXPECT_NE(automatic.culling[0].reason.find("auto: 4 boundary edges"), std::string::npos) << automatic.culling[0].reason;
  objects[0].back_face_culling = BackFaceCulling::kAlways;
  const LabelSummary forced = LabelSession(SessionReader::Open(dir / "S"), objects, LabelRig{}, Options(dir / "L"));
  EXPECT_TRUE(forced.culling[0].culled);
  std::ifstream manifest(dir / "L" / "label_manifest.json");
  const auto json = nlohmann::json::parse(manifest);
  EXPECT_EQ(json["back_face_culling"][0]["reason"], "always");

  std::ofstream(dir / "objects.yaml") << "objects:\n  - {id: 7, name: marker, mesh: marker.obj, unit: m, "
                                          "tracker_body: objbody, cull_back_faces: never}\n";
  EXPECT_EQ(ReadLabelObjects(dir / "objects.yaml")[0].back_face_culling, BackFaceCulling::kNever);
  std::ofstream(dir / "objects.yaml") << "objects:\n  - {id: 7, name: marker, mesh: marker.obj, unit: m, "
                                          "tracker_body: objbody, cull_back_faces: yes}\n";
  EXPECT_THROW(ReadLabelObjects(dir / "objects.yaml"), InputError);
}

TEST(Labeller, PoseConventionsEndToEnd) {
  // A known T_tracker_* chain must give T_camera_mesh in the record (rvec, t_m, quat_wxyz) and put the
  // marked vertex where cv::projectPoints puts it with that rvec / t_m.
  const auto dir = FreshDir("conventions");
  const testing::SyntheticRig rig;
  rig.WriteSession(dir / "S", 3);
  const std::vector<LabelObject> objects = {MarkerObject(dir, rig)};
  const LabelSummary summary = LabelSession(SessionReader::Open(dir / "S"), objects, LabelRig{}, Options(dir / "L"));
  ASSERT_TRUE(std::filesystem::exists(dir / "L" / "label_manifest.json"));
  EXPECT_EQ(summary.frames, 3);
  EXPECT_EQ(summary.records_with_pose, 3);
  EXPECT_FALSE(std::filesystem::exists(dir / "L.partial"));
  const auto lines = ReadJsonLines(dir / "L" / "labels.jsonl");
  ASSERT_EQ(lines.size(), 3u);
  const nlohmann::json& r = lines[0];
  const Eigen::Vector3d rvec(r["rvec"][0], r["rvec"][1], r["rvec"][2]);
  const Eigen::Vector3d t_m(r["t_m"][0], r["t_m"][1], r["t_m"][2]);
  EXPECT_LT((rvec - rig.T_camera_mesh.rvec()).norm(), 1e-9);
  EXPECT_LT((t_m - rig.T_camera_mesh.translation()).norm(), 1e-9);
  const Eigen::Vector4d q = rig.T_camera_mesh.quat_wxyz();
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(r["quat_wxyz"][i].get<double>(), q[i], 1e-9);
  EXPECT_EQ(r["object"], 7);
  EXPECT_TRUE(r["flags"].empty()) << r.dump();

  std::vector<cv::Point2d> expected;
  const PinholeCamera cam = testing::TestCamera();
  cv::projectPoints(std::vector<cv::Point3d>{{kMarker_mesh.x(), kMarker_mesh.y(), kMarker_mesh.z()}},
                    cv::Vec3d(rvec.x(), rvec.y(), rvec.z()), cv::Vec3d(t_m.x(), t_m.y(), t_m.z()),
                    cv::Matx33d(cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1), cv::noArray(), expected);
  ASSERT_TRUE(r.contains("mask_rect")) << r.dump();
  const auto& mr = r["mask_rect"];
  const PixelRect rect{mr[0], mr[1], mr[2], mr[3]};
  EXPECT_EQ(r["mask_row"], 0);  // the only object of the frame
  const ObjectMasks masks = ReadMaskFile(dir / "L" / "cam" / "mask_bits" / "000000.png", rect, false);
  const Image<uint8_t> amodal = ToFullImage(masks.amodal, rect, cam.width, cam.height);
  const cv::Moments m =
      cv::moments(cv::Mat(cam.height, cam.width, CV_8UC1, const_cast<uint8_t*>(amodal.data.data())), true);
  ASSERT_GT(m.m00, 0);
  EXPECT_NEAR(m.m10 / m.m00, expected[0].x, 0.5);
  EXPECT_NEAR(m.m01 / m.m00, expected[0].y, 0.5);
  // Default outputs: no BOP-style full-size masks.
  EXPECT_FALSE(std::filesystem::exists(dir / "L" / "cam" / "mask"));
  EXPECT_TRUE(std::filesystem::exists(dir / "L" / "cam" / "overlay" / "000000.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "L" / "cam" / "depth" / "000000.exr"));
  std::filesystem::remove_all(dir);
}

TEST(Labeller, PackedMasksEqualTheBopStyleMasks) {
  // Measured depth 0.7 m (in front of the marker at ~0.8 m: an occluder) in even columns, missing in odd
  // ones: under BOP19's rule the measured-depth mask keeps the odd columns only, and all three masks must
  // come back from the packed file exactly as the full-size files have them. Under the combined rule
  // (the default) the holes, enclosed by the nearer surface, are the occluder's: nothing is visible.
  const auto dir = FreshDir("packed");
  const testing::SyntheticRig rig;
  const PinholeCamera cam = testing::TestCamera();
  cv::Mat depth(cam.height, cam.width, CV_16UC1, cv::Scalar(0));
  for (int u = 0; u < cam.width; u += 2) depth.col(u).setTo(700);
  rig.WriteSession(dir / "S", 2, -1, -1, depth);
  LabelRunOptions options = Options(dir / "L");
  options.output.write_bop_masks = true;
  options.visibility.rule = VisibilityRule::kBop19;
  LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig)}, LabelRig{}, options);
  const auto lines = ReadJsonLines(dir / "L" / "labels.jsonl");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0]["visib_source"], "measured_depth");
  EXPECT_EQ(testing::CheckPackedMasks(dir / "L", lines), 2);
  const int all = lines[0]["px_count_all"], visib = lines[0]["px_count_visib"];
  EXPECT_GT(visib, 0);
  EXPECT_LT(visib, all);
  LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig)}, LabelRig{}, Options(dir / "L"));
  const auto combined = ReadJsonLines(dir / "L" / "labels.jsonl");
  EXPECT_EQ(combined[0]["px_count_all"], all);
  EXPECT_EQ(combined[0]["px_count_visib"], 0);
  std::filesystem::remove_all(dir);
}

TEST(Labeller, ClassImageHoldsEachInstancePixelsObjectId) {
  // Two objects (ids 7 and 9), the second on the camera's body 3 cm beside the first: every pixel of the
  // class image is the object id of the instance the instance image names there, 0 on the background.
  const auto dir = FreshDir("classes");
  const testing::SyntheticRig rig;
  rig.WriteSession(dir / "S", 1);
  LabelObject second = MarkerObject(dir, rig);
  second.id = 9, second.name = "second";
  second.mounts[0] = {"cambody", rig.T_cambody_camera * rig.T_camera_mesh * Rigid3d::FromRvec({0, 0, 0}, {0.03, 0, 0})};
  LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig), second}, LabelRig{}, Options(dir / "L"));
  std::map<int, int> object_of_instance;
  for (const auto& line : ReadJsonLines(dir / "L" / "labels.jsonl")) object_of_instance[line["instance"]] = line["object"];
  ASSERT_EQ(object_of_instance.size(), 2u);
  const cv::Mat instances = cv::imread((dir / "L" / "cam" / "instance" / "000000.png").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat classes = cv::imread((dir / "L" / "cam" / "class" / "000000.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(classes.type(), CV_16UC1);
  std::map<int, int> pixels_of_class;
  for (int v = 0; v < classes.rows; ++v)
    for (int u = 0; u < classes.cols; ++u) {
      const int instance = instances.at<uint16_t>(v, u), object = classes.at<uint16_t>(v, u);
      ASSERT_EQ(object, instance == 0 ? 0 : object_of_instance.at(instance)) << "pixel " << u << ", " << v;
      ++pixels_of_class[object];
    }
  EXPECT_GE(pixels_of_class[7], 3);  // a 6 mm square 0.8 m away
  EXPECT_GE(pixels_of_class[9], 3);
  std::filesystem::remove_all(dir);
}

TEST(Labeller, TrackerDropoutIsFlaggedNotFilled) {
  const auto dir = FreshDir("dropout");
  const testing::SyntheticRig rig;
  // Frame 1 is stamped 53 ms: its object samples (50 and 60 ms) are missing.
  rig.WriteSession(dir / "S", 3, 45 * kMs, 65 * kMs);
  const LabelSummary summary =
      LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig)}, LabelRig{}, Options(dir / "L"));
  EXPECT_EQ(summary.records_with_pose, 2);
  EXPECT_EQ(summary.flag_counts.at("missing_body"), 1);
  const auto lines = ReadJsonLines(dir / "L" / "labels.jsonl");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_FALSE(lines[1].contains("rvec"));
  EXPECT_NE(lines[1]["reason"].get<std::string>().find("missing"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(Labeller, LatencyShiftsTheTrackerTime) {
  // With a latency of -15 ms the frames (20, 53, 86 ms) read tracker times 5, 38 and 71 ms, whose
  // bracketing samples all lie outside the [45, 65) dropout; without it frame 1 falls inside.
  const auto dir = FreshDir("latency");
  const testing::SyntheticRig rig;
  rig.WriteSession(dir / "S", 3, 45 * kMs, 65 * kMs);
  LabelRig latency;
  latency.tracker_latency_ns = -15 * kMs;
  const LabelSummary summary =
      LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig)}, latency, Options(dir / "L"));
  EXPECT_EQ(summary.records_with_pose, 3);
  std::filesystem::remove_all(dir);
}

TEST(Labeller, BodyNamesAreTheUsersText) {
  // A TUM import names its camera body "camera", and a tracker body may be called "tracker": body names
  // must not collide with the labeller's own frame names (issue: "frame 'camera' linked to itself").
  const auto dir = FreshDir("body_names");
  testing::SyntheticRig rig;
  rig.cambody = "camera";
  rig.objbody = "tracker";
  rig.WriteSession(dir / "S", 2);
  const LabelSummary summary =
      LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig)}, LabelRig{}, Options(dir / "L"));
  EXPECT_EQ(summary.records_with_pose, 2);
  const auto lines = ReadJsonLines(dir / "L" / "labels.jsonl");
  ASSERT_EQ(lines.size(), 2u);
  const Eigen::Vector3d t_m(lines[0]["t_m"][0], lines[0]["t_m"][1], lines[0]["t_m"][2]);
  EXPECT_LT((t_m - rig.T_camera_mesh.translation()).norm(), 1e-9);
  std::filesystem::remove_all(dir);
}

TEST(Labeller, ACorruptDepthFileFlagsItsFrameInsteadOfStoppingTheRun) {
  const auto dir = FreshDir("corrupt_depth");
  const testing::SyntheticRig rig;
  const cv::Mat depth(testing::TestCamera().height, testing::TestCamera().width, CV_16UC1, cv::Scalar(790));
  rig.WriteSession(dir / "S", 3, -1, -1, depth);
  const SessionReader session = SessionReader::Open(dir / "S");
  const std::filesystem::path depth_file =
      dir / "S" / "cameras" / "cam" / session.frame("cam", 1).record.depth_file;
  const auto size = std::filesystem::file_size(depth_file);
  std::filesystem::resize_file(depth_file, size / 2);  // a PNG cut in half
  const LabelSummary summary = LabelSession(session, {MarkerObject(dir, rig)}, LabelRig{}, Options(dir / "L"));
  EXPECT_EQ(summary.frames, 3);
  EXPECT_EQ(summary.flag_counts.at("unreadable_depth"), 1);
  const auto lines = ReadJsonLines(dir / "L" / "labels.jsonl");
  ASSERT_EQ(lines.size(), 3u);
  for (const auto& line : lines) {
    const bool corrupt = line["index"] == 1;
    EXPECT_EQ(line["flags"].dump().find("unreadable_depth") != std::string::npos, corrupt) << line.dump();
    if (corrupt) {
      EXPECT_NE(line["reason"].get<std::string>().find(depth_file.filename().string()), std::string::npos);
    }
    EXPECT_TRUE(line.contains("rvec")) << "the pose does not depend on the depth file";
  }
  LabelRunOptions strict = Options(dir / "L2");
  strict.stop_on_unreadable_image = true;
  EXPECT_THROW(LabelSession(session, {MarkerObject(dir, rig)}, LabelRig{}, strict), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "L2"));
  std::filesystem::remove_all(dir);
}

TEST(Labeller, ASessionWithoutACameraSaysSo) {
  const auto dir = FreshDir("no_camera");
  testing::SyntheticRig rig;
  rig.with_camera = false;
  rig.WriteSession(dir / "S", 2);
  try {
    LabelSession(SessionReader::Open(dir / "S"), {MarkerObject(dir, rig)}, LabelRig{}, Options(dir / "L"));
    ADD_FAILURE() << "a session without a camera was labelled";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no camera stream"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "L"));
  EXPECT_FALSE(std::filesystem::exists(dir / "L.partial"));
  std::filesystem::remove_all(dir);
}

TEST(Labeller, BadInputGivesClearErrors) {
  const auto dir = FreshDir("bad");
  const testing::SyntheticRig rig;
  rig.WriteSession(dir / "S", 1);
  const SessionReader session = SessionReader::Open(dir / "S");
  LabelObject missing = MarkerObject(dir, rig);
  missing.mesh_path = dir / "nope.ply";
  try {
    LabelSession(session, {missing}, LabelRig{}, Options(dir / "L1"));
    ADD_FAILURE() << "a missing mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.ply"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "L1"));

  // A BOP model (millimetres) declared as metres is 1000x too large.
  LabelObject wrong_unit = MarkerObject(dir, rig);
  wrong_unit.mesh_path = std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2/models/obj_000001.ply";
  try {
    LabelSession(session, {wrong_unit}, LabelRig{}, Options(dir / "L2"));
    ADD_FAILURE() << "a mesh in mm declared as metres was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("obj_000001.ply"), std::string::npos) << e.what();
  }

  LabelRig no_body;
  no_body.cameras.push_back({.camera = "cam", .color_camera = {}, .body = "headbody", .T_body_camera = {}, .T_color_depth = {}});
  EXPECT_THROW(LabelSession(session, {MarkerObject(dir, rig)}, no_body, Options(dir / "L3")), InputError);

  LabelObject unknown_body = MarkerObject(dir, rig);
  unknown_body.mounts[0].body = "ghost";
  const LabelSummary s = LabelSession(session, {unknown_body}, LabelRig{}, Options(dir / "L4"));
  EXPECT_EQ(s.flag_counts.at("missing_body"), 1);

  // Refuses to overwrite a folder that is not an earlier label output.
  std::filesystem::create_directories(dir / "precious");
  std::ofstream(dir / "precious" / "data.txt") << "keep";
  EXPECT_THROW(LabelSession(session, {MarkerObject(dir, rig)}, LabelRig{}, Options(dir / "precious")), InputError);
  EXPECT_TRUE(std::filesystem::exists(dir / "precious" / "data.txt"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mocap
