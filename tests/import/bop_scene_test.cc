#include "session/import/bop_scene.h"

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::InputErrorOf;
using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

const std::string kScene = "bop_lmo_scene2/test/000002";
const std::string kModels = "bop_lmo_scene2/models";

TEST(BopScene, ImportsOnlyFramesWithColourImages) {
  const auto scene = ReadBopScene(RealData(kScene), RealData(kModels));
  EXPECT_EQ(scene.scene_id, 2);
  EXPECT_EQ(scene.annotated_frames, 200);
  ASSERT_EQ(scene.frames.size(), 10u);
  EXPECT_EQ(scene.frames_without_rgb, 190);
  std::vector<int> ids;
  for (const auto& f : scene.frames) ids.push_back(f.im_id);
  EXPECT_EQ(ids, (std::vector<int>{3, 8, 17, 27, 36, 38, 39, 41, 47, 58}));
  EXPECT_EQ(scene.models.size(), 8u);
  for (const auto& m : scene.models) EXPECT_TRUE(m.mesh_exists) << m.mesh;
  EXPECT_NEAR(scene.models.front().diameter_m, 0.102099, 1e-12);
}

TEST(BopScene, PosesAreModelToCameraInMetres) {
  const auto scene = ReadBopScene(RealData(kScene), RealData(kModels));
  const auto gt = nlohmann::json::parse(ReadAll(RealData(kScene + "/scene_gt.json")));
  const auto& frame = scene.frames.front();
  ASSERT_EQ(frame.objects.size(), gt["3"].size());
  for (size_t k = 0; k < frame.objects.size(); ++k) {
    const auto& o = frame.objects[k];
    const auto& e = gt["3"][k];
    EXPECT_EQ(o.obj_id, e["obj_id"].get<int>());
    EXPECT_EQ(o.instance, 0);
    // p_camera = R p_model + t, with t in mm: check on a model point 5 cm out along x.
    Eigen::Matrix3d R;
    for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = e["cam_R_m2c"][static_cast<size_t>(i)].get<double>();
    const Eigen::Vector3d t_mm(e["cam_t_m2c"][0].get<double>(), e["cam_t_m2c"][1].get<double>(), e["cam_t_m2c"][2].get<double>());
    const Eigen::Vector3d p_model_mm(50, 0, 0);
    const Eigen::Vector3d expected_m = (R * p_model_mm + t_mm) * 1e-3;
    // LM-O's R is not exactly orthonormal (|R R^T - I| up to 0.016); the nearest rotation moves a
    // point 5 cm from the model origin by well under 0.1 mm.
    EXPECT_LT((o.T_camera_object * (p_model_mm * 1e-3) - expected_m).norm(), 1e-4);
    EXPECT_LT((o.T_camera_object.translation() - t_mm * 1e-3).norm(), 1e-12);
  }
  EXPECT_EQ(frame.camera.width, 640);
  EXPECT_EQ(frame.camera.height, 480);
  EXPECT_EQ(frame.camera.fx, 572.4114);
  EXPECT_EQ(frame.camera.cy, 242.04899);
  EXPECT_TRUE(frame.depth.empty());
  EXPECT_EQ(BopObjectName(12), "obj_000012");
}

// A small scene written from scratch: two instances of one object, depth present, K on frame 1 only.
struct TinyScene {
  ScratchDir dir;
  std::filesystem::path scene, models;
  TinyScene(const std::string& gt, const std::string& cameras, const std::string& info = R"({"1": {"diameter": 80.0}})") {
    scene = dir.path() / "000007";
    models = dir.path() / "models";
    dir.Write("models/models_info.json", info);
    dir.Write("models/obj_000001.ply", "ply\n");
    dir.Write("000007/scene_gt.json", gt);
    dir.Write("000007/scene_camera.json", cameras);
    // A 4x3 PNG header is all the reader looks at for the size.
    const std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\0\0\x04\0\0\0\x03\x08\x02\0\0\0", 29);
    dir.Write("000007/rgb/000001.png", png);
    dir.Write("000007/depth/000001.png", png);
  }
};

constexpr const char* kCam = R"({"1": {"cam_K": [500, 0, 2, 0, 500, 1.5, 0, 0, 1], "depth_scale": 0.1}})";
constexpr const char* kTwoInstances =
    R"({"1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 900], "obj_id": 1},
              {"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [10, 0, 950], "obj_id": 1}],
        "2": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 900], "obj_id": 1}]})";

TEST(BopScene, SeveralInstancesAndDepth) {
  TinyScene tiny(kTwoInstances, kCam);
  const auto scene = ReadBopScene(tiny.scene, tiny.models);
  EXPECT_EQ(scene.scene_id, 7);
  ASSERT_EQ(scene.frames.size(), 1u);
  EXPECT_EQ(scene.frames_without_rgb, 1);
  const auto& f = scene.frames[0];
  EXPECT_EQ(f.camera.width, 4);
  EXPECT_EQ(f.camera.height, 3);
  EXPECT_EQ(f.depth_scale_mm, 0.1);
  EXPECT_FALSE(f.depth.empty());
  ASSERT_EQ(f.objects.size(), 2u);
  EXPECT_EQ(f.objects[1].instance, 1);
  EXPECT_EQ(f.objects[1].gt_index, 1);
  EXPECT_NEAR(f.objects[1].T_camera_object.translation().z(), 0.95, 1e-12);
}

TEST(BopScene, BadScenesAreRefusedWithTheirPlace) {
  {
    TinyScene metres(R"({"1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 0.9], "obj_id": 1}]})", kCam);
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(metres.scene, metres.models); }), HasSubstr("were metres written?"));
  }
  {
    TinyScene model_m(kTwoInstances, kCam, R"({"1": {"diameter": 0.08}})");
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(model_m.scene, model_m.models); }), HasSubstr("looks like metres"));
  }
  {
    TinyScene torn(std::string(kTwoInstances).substr(0, 60), kCam);
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(torn.scene, torn.models); }), HasSubstr("scene_gt.json: byte "));
  }
  {
    TinyScene no_t(R"({"1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "obj_id": 1}]})", kCam);
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(no_t.scene, no_t.models); }), HasSubstr("\"1\"[0]: missing \"cam_t_m2c\""));
  }
  {
    TinyScene unknown(R"({"1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0,0,900], "obj_id": 4}]})", kCam);
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(unknown.scene, unknown.models); }), HasSubstr("obj_id 4 is not in models_info"));
  }
  {  // found by tests/fuzz (fuzz_bop): nlohmann's number overflow escaped as a bare out_of_range exception
    TinyScene overflow(R"({"1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0,0,9e999], "obj_id": 1}]})", kCam);
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(overflow.scene, overflow.models); }),
                AllOf(HasSubstr("scene_gt.json: invalid JSON"), HasSubstr("number overflow")));
  }
  {
    TinyScene skew(kTwoInstances, R"({"1": {"cam_K": [500, 3, 2, 0, 500, 1.5, 0, 0, 1], "depth_scale": 1}})");
    EXPECT_THAT(InputErrorOf([&] { ReadBopScene(skew.scene, skew.models); }), HasSubstr("cam_K: not a pinhole matrix"));
  }
}

}  // namespace
}  // namespace mocap::import
