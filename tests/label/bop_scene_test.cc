// Real data: BOP LM-O test scene 2 (Kinect v1 images, scanned meshes in mm, ground-truth poses). The
// renderer + label statistics must reproduce BOP's own scene_gt_info.json: bbox_obj within 2 px and
// px_count_all within 3% for every object of the 10 frames with RGB; visib_fract from the model
// z-buffer is close to the file's where no unmodelled occluder hides the object (the file's values
// used measured depth, which also sees the unannotated LINEMOD objects standing in the scene).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "label/object_labels.h"

namespace mocap {
namespace {

const std::string kRoot = std::string(MOCAP_SHARED_DIR) + "/realdata/bop_lmo_scene2";

nlohmann::json ReadJson(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  return nlohmann::json::parse(in);
}

TEST(BopScene, RenderedStatsMatchSceneGtInfo) {
  const auto scene_gt = ReadJson(kRoot + "/test/000002/scene_gt.json");
  const auto scene_info = ReadJson(kRoot + "/test/000002/scene_gt_info.json");
  const auto scene_camera = ReadJson(kRoot + "/test/000002/scene_camera.json");
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer renderer(*context);
  std::map<int, MeshHandle> meshes;
  for (int id : {1, 5, 6, 8, 9, 10, 11, 12}) {
    char name[32];
    std::snprintf(name, sizeof(name), "/models/obj_%06d.ply", id);
    meshes[id] = renderer.Upload(LoadMesh(kRoot + name, 0.001));
  }
  int objects = 0;
  double visib_error_sum = 0;
  int visib_compared = 0;
  for (int frame : {3, 8, 17, 27, 36, 38, 39, 41, 47, 58}) {
    const std::string key = std::to_string(frame);
    const auto& K = scene_camera[key]["cam_K"];
    const PinholeCamera camera{640, 480, K[0], K[4], K[2], K[5], {}};
    std::vector<RenderItem> items;
    for (const auto& gt : scene_gt[key]) {
      Eigen::Matrix3d R;
      for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = gt["cam_R_m2c"][i];
      const Eigen::Vector3d t(gt["cam_t_m2c"][0], gt["cam_t_m2c"][1], gt["cam_t_m2c"][2]);
      // The file's rotations are orthonormal to ~1e-8; re-orthonormalise for Rigid3d's precondition.
      const Eigen::Quaterniond q(R);
      items.push_back({meshes.at(gt["obj_id"]), Rigid3d(q.normalized(), t / 1000.0), static_cast<uint16_t>(items.size() + 1)});
    }
    const auto labels = ComputeObjectLabels(renderer.Render(camera, items), camera, nullptr);
    for (size_t k = 0; k < labels.size(); ++k) {
      const auto& expected = scene_info[key][k];
      const ObjectStats& s = labels[k].stats;
      for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(s.bbox_obj[i], expected["bbox_obj"][i].get<int>(), 2) << "frame " << frame << " object " << k << " bbox[" << i << "]";
      const double all = expected["px_count_all"];
      EXPECT_NEAR(s.px_count_all, all, 0.03 * all) << "frame " << frame << " object " << k;
      const double visib = expected["visib_fract"];
      // Model visibility is mostly above the file's depth-based one (it misses unmodelled occluders);
      // it can be lower by a little at occlusion boundaries, where BOP's 15 mm tolerance lets the
      // occluded object through.
      EXPECT_GT(s.visib_fract_model, visib - 0.1) << "frame " << frame << " object " << k;
      if (visib > 0.9) {
        EXPECT_GT(s.visib_fract_model, visib - 0.02) << "frame " << frame << " object " << k;
        visib_error_sum += std::abs(s.visib_fract_model - visib), ++visib_compared;
      }
      ++objects;
    }
  }
  EXPECT_GE(objects, 60);
  ASSERT_GT(visib_compared, 10);
  EXPECT_LT(visib_error_sum / visib_compared, 0.05) << "mean |visib_fract| difference on unoccluded objects";
}

}  // namespace
}  // namespace mocap
