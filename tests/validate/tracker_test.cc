#include "validate/tracker.h"

#include <gtest/gtest.h>

#include "synthetic.h"
#include "validate/label_check.h"

namespace mocap {
namespace {

/// A box, its crops at the validator's and at a sensor's resolution, and a camera that circles it at
/// 0.9 m, looking at it.
struct CircledBox {
  SurfaceCropSource model = SurfaceCropSource::FromMesh(testing::BoxMesh({0.16, 0.06, 0.21}), CropOptions{});
  SurfaceCropSource sensor =
      SurfaceCropSource::FromMesh(testing::BoxMesh({0.16, 0.06, 0.21}), CropOptions{.pixel_m = 0.002});
  Rigid3d T_world_object = Rigid3d::FromRvec({0.2, 0.1, 0.4}, {0.0, 0.0, 0.0});
  static Rigid3d T_camera_world(double angle_deg) {
    const double a = RadFromDeg(angle_deg);
    return LookAt(Eigen::Vector3d(0.9 * std::sin(a), -0.9 * std::cos(a), 0.2), Eigen::Vector3d::Zero(),
                  Eigen::Vector3d::UnitZ());
  }
};


TEST(ObjectTracker, AcquiresThenTracksAStaticObjectWhileTheCameraMoves) {
  const CircledBox box;
  ValidateOptions options;
  options.acquisition.roll_steps = 4;
  ObjectTracker tracker(box.model, options);
  std::mt19937 rng(3);
  for (int k = 0; k < 12; ++k) {
    const Rigid3d T_camera_world = CircledBox::T_camera_world(5.0 * k);  // 5 degrees per frame
    const Rigid3d T_camera_object = T_camera_world * box.T_world_object;
    const PointCloud scene =
        testing::AddNoise(Transform(T_camera_object, box.sensor.Crop(T_camera_object).points_model), rng, 0.001);
    const int64_t stamp_ns = k * 33'333'333LL;
    PointCloud input = k == 6 ? PointCloud{} : scene;  // frame 6: the object is occluded
    const TrackStep step = tracker.Step(input, T_camera_world.inverse(), stamp_ns);
    ASSERT_TRUE(step.has_pose) << "frame " << k << ": " << step.note;
    EXPECT_EQ(step.mode, k == 0 ? TrackMode::kAcquisition : TrackMode::kTracking) << "frame " << k;
    if (k == 6) {
      EXPECT_FALSE(step.measured);
    } else {
      EXPECT_GT(step.score, 0.9) << "frame " << k;
    }
    // The box's 180-degree flips look identical; the test scene breaks none of them, so compare the
    // position and the visible geometry only.
    EXPECT_LT(TranslationDistanceM(step.T_camera_object, T_camera_object), 0.003) << "frame " << k;
  }
}

/// A tracked frame's label check takes the tracking step's index and converged refinement instead of
/// making them again: its estimate, analysis and verdict are the ones it makes without them.
TEST(ObjectTracker, ALabelCheckTakesTheTrackingStepsRefinementAsItsOwn) {
  const CircledBox box;
  ValidateOptions options;
  options.acquisition.roll_steps = 4;
  options.scene_voxel_m = 0;  // thinned once before the step, as the session check does
  ObjectTracker tracker(box.model, options);
  std::mt19937 rng(5);
  for (int k = 0; k < 6; ++k) {
    const Rigid3d T_camera_world = CircledBox::T_camera_world(4.0 * k);
    const Rigid3d T_camera_object = T_camera_world * box.T_world_object;
    PointCloud scene = VoxelDownsample(
        testing::AddNoise(Transform(T_camera_object, box.sensor.Crop(T_camera_object).points_model), rng, 0.001), 0.003);
    // From frame 3 on, a few points far behind the object (the mask's edge on the background): the
    // tracking step's box leaves them out of its index.
    if (k >= 3)
      for (int i = 0; i < 20; ++i) scene.push_back(T_camera_object * Eigen::Vector3d(0.0, 0.0, 0.0) + Eigen::Vector3d(0.01 * i, 0, 0.4));
    // The label seeds the acquisition, as in the session check (a box's 180-degree turns look alike).
    const TrackStep step = tracker.Step(scene, T_camera_world.inverse(), k * 33'333'333LL, &T_camera_object);
    ASSERT_TRUE(step.measured) << "frame " << k << ": " << step.note;
    ASSERT_TRUE(step.scene_grid) << "frame " << k;
    if (k == 0) {
      EXPECT_EQ(step.mode, TrackMode::kAcquisition);
      EXPECT_EQ(step.scene_grid->size(), scene.size());
      EXPECT_FALSE(step.refinement);
      continue;
    }
    ASSERT_EQ(step.mode, TrackMode::kTracking) << "frame " << k;
    ASSERT_TRUE(step.refinement) << "frame " << k;
    EXPECT_EQ(step.scene_grid->size(), k >= 3 ? scene.size() - 20 : scene.size()) << "frame " << k;
    EXPECT_EQ(step.refinement->T_camera_object.translation(), step.T_camera_object_measured.translation());
    TrackStep without = step;  // as a step that kept neither
    without.refinement.reset();
    without.scene_grid.reset();
    const LabelCheck taken = CheckLabelWithTrack(scene, T_camera_object, box.model, step, options);
    const LabelCheck made = CheckLabelWithTrack(scene, T_camera_object, box.model, without, options);
    EXPECT_EQ(taken.verdict, Verdict::kAccept) << "frame " << k << ": " << taken.reason;
    EXPECT_EQ(taken.verdict, made.verdict) << "frame " << k;
    EXPECT_EQ(taken.observability.observable, made.observability.observable) << "frame " << k;
    EXPECT_LT(TranslationDistanceM(taken.T_camera_object_segicp, made.T_camera_object_segicp), 1e-4) << "frame " << k;
    EXPECT_LT(RotationDistanceDeg(taken.T_camera_object_segicp, made.T_camera_object_segicp), 0.05) << "frame " << k;
    EXPECT_NEAR(taken.segicp_score, made.segicp_score, 0.01) << "frame " << k;
    EXPECT_NEAR(taken.label_score, made.label_score, 0.01) << "frame " << k;
  }
}

}  // namespace
}  // namespace mocap
