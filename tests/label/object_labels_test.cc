#include "label/object_labels.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "core/check.h"
#include "render/primitives.h"

namespace mocap {
namespace {

const PinholeCamera kCamera{640, 480, 525.0, 525.0, 319.5, 239.5, {}};

class ObjectLabelsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    context_ = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
    renderer_ = std::make_unique<Renderer>(*context_);
    const MeshHandle box = renderer_->Upload(MakeBoxMesh({0.2, 0.2, 0.2}));
    items_ = {{box, Rigid3d::FromRvec({0, 0, 0}, {0.0, 0.0, 1.0}), 1},     // front
              {box, Rigid3d::FromRvec({0.3, 0.2, 0}, {0.1, 0.05, 1.3}), 2},  // behind, half hidden
              {box, Rigid3d::FromRvec({0, 0, 0}, {0.9, 0.0, 1.2}), 3}};    // cut by the right border
    render_ = renderer_->Render(kCamera, items_);
  }
  std::unique_ptr<RenderContext> context_;
  std::unique_ptr<Renderer> renderer_;
  std::vector<RenderItem> items_;
  RenderOutput render_;
};

TEST_F(ObjectLabelsTest, ModelVisibleMasksPartitionTheImage) {
  const auto labels = ComputeObjectLabels(render_, kCamera, nullptr);
  ASSERT_EQ(labels.size(), 3u);
  Image<int> owners(kCamera.width, kCamera.height, 0);
  int visible_total = 0;
  for (const auto& l : labels) {
    for (int v = 0; v < kCamera.height; ++v) {
      for (int u = 0; u < kCamera.width; ++u) {
        if (l.masks.at(l.masks.visible_model, u, v)) {
          ++owners.at(u, v);
          EXPECT_TRUE(l.masks.at(l.masks.amodal, u, v)) << "visible is a subset of amodal";
        }
      }
    }
    visible_total += l.stats.px_count_visib_model;
  }
  int covered = 0;
  for (int v = 0; v < kCamera.height; ++v) {
    for (int u = 0; u < kCamera.width; ++u) {
      EXPECT_LE(owners.at(u, v), 1) << "pixel " << u << "," << v << " owned twice";
      EXPECT_EQ(owners.at(u, v) == 1, render_.instance_ids.at(u, v) != 0);
      covered += render_.instance_ids.at(u, v) != 0;
    }
  }
  EXPECT_EQ(visible_total, covered);
  const ObjectStats& hidden = labels[1].stats;
  EXPECT_GT(hidden.px_count_visib_model, 0);
  EXPECT_LT(hidden.visib_fract_model, 0.9);
  EXPECT_EQ(hidden.px_count_valid, -1) << "no measured depth";
  EXPECT_EQ(hidden.px_count_visib, hidden.px_count_visib_model) << "without depth, visibility is the model's";
}

TEST_F(ObjectLabelsTest, TruncatedObjectKeepsItsAmodalBox) {
  const auto labels = ComputeObjectLabels(render_, kCamera, nullptr);
  const ObjectStats& cut = labels[2].stats;
  // Box 3 spans x 0.8..1.0 m, z 1.1..1.3 m; its leftmost image point is the back-left edge (x 0.8 m,
  // z 1.3 m): u = 319.5 + 525 * 0.8 / 1.3 = 642.6, so the first covered column is 643, just outside.
  EXPECT_EQ(cut.bbox_obj[0], 643);
  EXPECT_NEAR(cut.bbox_obj[0] + cut.bbox_obj[2], 319.5 + 525.0 * 1.0 / 1.1, 1.0) << "x_max: front face";
  EXPECT_TRUE(cut.outside_image);
  EXPECT_EQ(cut.px_count_visib, 0);
  EXPECT_EQ(cut.bbox_visib, (PixelBox{-1, -1, -1, -1}));
  EXPECT_DOUBLE_EQ(cut.visib_fract, 0.0);
  EXPECT_GT(cut.px_count_all, 0);
}

TEST_F(ObjectLabelsTest, MeasuredDepthRuleFollowsBop19) {
  // Measured depth = the rendered scene, with: a hole (no depth) on object 1, and an unmodelled
  // occluder 10 cm in front of object 1 elsewhere.
  DepthImage measured = render_.depth_m;
  for (int v = 240; v < 260; ++v)
    for (int u = 340; u < 360; ++u) measured.at(u, v) = 0.0f;  // missing: counts as visible
  for (int v = 270; v < 290; ++v)
    for (int u = 270; u < 290; ++u) measured.at(u, v) -= 0.10f;  // hand in front: not visible
  const auto labels = ComputeObjectLabels(render_, kCamera, &measured, {.rule = VisibilityRule::kBop19});
  const ObjectLabels& front = labels[0];
  EXPECT_TRUE(front.masks.at(front.masks.visible_measured, 350, 250));
  EXPECT_FALSE(front.masks.at(front.masks.visible_measured, 280, 280));
  EXPECT_TRUE(front.masks.at(front.masks.visible_model, 280, 280)) << "the model knows no hand";
  EXPECT_EQ(front.stats.px_count_visib, front.stats.px_count_all - 400);
  EXPECT_EQ(front.stats.px_count_valid, front.stats.px_count_all - 400);
  // The hidden object: where it is hidden, the measured surface (object 1) is ~0.3 m in front, beyond
  // delta: not visible; except in the hole, where missing depth counts as visible (BOP19).
  const ObjectLabels& hidden = labels[1];
  int hidden_in_hole = 0;
  for (int v = 240; v < 260; ++v)
    for (int u = 340; u < 360; ++u)
      hidden_in_hole += hidden.masks.at(hidden.masks.amodal, u, v) && !hidden.masks.at(hidden.masks.visible_model, u, v);
  EXPECT_GT(hidden_in_hole, 0);
  EXPECT_EQ(hidden.stats.px_count_visib, hidden.stats.px_count_visib_model + hidden_in_hole);
}

TEST_F(ObjectLabelsTest, CombinedRuleKeepsModelledOccludersAndMeasuredOnes) {
  // The same depth as above under the default (combined) rule: the hole on object 1 is its own surface
  // (visible), the hand still hides object 1, and object 2 gets nothing of object 1's hole.
  DepthImage measured = render_.depth_m;
  for (int v = 240; v < 260; ++v)
    for (int u = 340; u < 360; ++u) measured.at(u, v) = 0.0f;
  for (int v = 270; v < 290; ++v)
    for (int u = 270; u < 290; ++u) measured.at(u, v) -= 0.10f;
  const auto labels = ComputeObjectLabels(render_, kCamera, &measured);
  const ObjectLabels& front = labels[0];
  EXPECT_TRUE(front.masks.at(front.masks.visible_measured, 350, 250));
  EXPECT_FALSE(front.masks.at(front.masks.visible_measured, 280, 280));
  EXPECT_EQ(front.stats.px_count_visib, front.stats.px_count_all - 400);
  EXPECT_EQ(front.stats.px_count_visib_assumed, 400);
  for (const ObjectLabels& l : labels)
    for (size_t i = 0; i < l.masks.visible_measured.size(); ++i)
      ASSERT_LE(l.masks.visible_measured[i], l.masks.visible_model[i]) << "a subset of the z-buffer's mask";
  EXPECT_EQ(labels[1].stats.px_count_visib, labels[1].stats.px_count_visib_model);
}

TEST_F(ObjectLabelsTest, DeltaGrowsWithDepth) {
  const VisibilityOptions options;
  EXPECT_NEAR(options.delta_m(1.0), 0.015 + 3 * 1.425e-3, 1e-12);
  EXPECT_NEAR(options.delta_m(2.0), 0.015 + 3 * 1.425e-3 * 4, 1e-12);
  const VisibilityOptions bop{.noise_sigmas = 0};
  EXPECT_DOUBLE_EQ(bop.delta_m(3.0), 0.015);
  // A measured surface 17 mm in front of the rendered one at 1 m: visible with the default delta
  // (19.3 mm), not with BOP's fixed 15 mm.
  DepthImage measured = render_.depth_m;
  for (float& z : measured.data)
    if (z > 0) z -= 0.017f;
  const auto adaptive = ComputeObjectLabels(render_, kCamera, &measured, options);
  const auto fixed = ComputeObjectLabels(render_, kCamera, &measured, bop);
  EXPECT_GT(adaptive[0].stats.px_count_visib, 0.9 * adaptive[0].stats.px_count_all);
  EXPECT_LT(fixed[0].stats.px_count_visib, 0.1 * fixed[0].stats.px_count_all);
  EXPECT_THROW((VisibilityOptions{.delta_base_m = -1}.check()), InputError);
}

TEST_F(ObjectLabelsTest, WrongDepthSizeIsAnError) {
  const DepthImage small(320, 240, 1.0f);
  EXPECT_THROW(ComputeObjectLabels(render_, kCamera, &small), InputError);
}

TEST(MaskBox, MatchesEveryPixelScan) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 300; ++trial) {
    const PixelRect rect{static_cast<int>(rng() % 50), static_cast<int>(rng() % 50), 1 + static_cast<int>(rng() % 40),
                         1 + static_cast<int>(rng() % 40)};
    std::vector<uint8_t> mask(static_cast<size_t>(rect.width) * rect.height, 0);
    const int fill = static_cast<int>(rng() % 4);  // 0: empty mask, else about 1 pixel in 20, 100, 1000
    for (uint8_t& m : mask) m = fill > 0 && rng() % (fill == 1 ? 20 : fill == 2 ? 100 : 1000) == 0 ? 1 : 0;
    int x0 = INT32_MAX, y0 = INT32_MAX, x1 = -1, y1 = -1;
    for (int v = 0; v < rect.height; ++v)
      for (int u = 0; u < rect.width; ++u)
        if (mask[static_cast<size_t>(v) * rect.width + u])
          x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, v), y1 = std::max(y1, v);
    const PixelBox expected =
        x1 < 0 ? PixelBox{-1, -1, -1, -1} : PixelBox{rect.x + x0, rect.y + y0, x1 - x0, y1 - y0};
    EXPECT_EQ(MaskBox(mask, rect), expected) << "trial " << trial;
  }
}

TEST(PoseFields, ObjectToCameraInOpenCvAxes) {
  // 90 degrees about the camera's y axis, 1 m ahead: rvec (0, pi/2, 0), quaternion (w, x, y, z) =
  // (cos 45, 0, sin 45, 0); the object's x axis points along the camera's -z.
  const Rigid3d T_camera_object = Rigid3d::FromRvec({0, std::numbers::pi / 2, 0}, {0.1, -0.2, 1.0});
  const PoseFields f = MakePoseFields(T_camera_object);
  EXPECT_NEAR(f.rvec.y(), std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(f.rvec.x(), 0, 1e-12);
  EXPECT_NEAR(f.quat_wxyz[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(f.quat_wxyz[2], std::sqrt(0.5), 1e-12);
  EXPECT_EQ(f.t_m, Eigen::Vector3d(0.1, -0.2, 1.0));
  EXPECT_NEAR((T_camera_object.rotation() * Eigen::Vector3d::UnitX()).z(), -1.0, 1e-12);
}

}  // namespace
}  // namespace mocap
