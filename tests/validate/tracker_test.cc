#include "validate/tracker.h"

#include <gtest/gtest.h>

#include "synthetic.h"

namespace mocap {
namespace {


TEST(ObjectTracker, AcquiresThenTracksAStaticObjectWhileTheCameraMoves) {
  const TriangleMesh mesh = testing::BoxMesh({0.16, 0.06, 0.21});
  const SurfaceCropSource model = SurfaceCropSource::FromMesh(mesh, CropOptions{});
  const SurfaceCropSource sensor = SurfaceCropSource::FromMesh(mesh, CropOptions{.pixel_m = 0.002});
  const Rigid3d T_world_object = Rigid3d::FromRvec({0.2, 0.1, 0.4}, {0.0, 0.0, 0.0});
  ValidateOptions options;
  options.acquisition.roll_steps = 4;
  ObjectTracker tracker(model, options);
  std::mt19937 rng(3);
  for (int k = 0; k < 12; ++k) {
    // The camera circles the object at 0.9 m, 5 degrees per frame, looking at it.
    const double a = RadFromDeg(5.0 * k);
    const Rigid3d T_camera_world =
        LookAt(Eigen::Vector3d(0.9 * std::sin(a), -0.9 * std::cos(a), 0.2), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
    const Rigid3d T_camera_object = T_camera_world * T_world_object;
    const PointCloud scene = testing::AddNoise(Transform(T_camera_object, sensor.Crop(T_camera_object).points_model), rng, 0.001);
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

}  // namespace
}  // namespace mocap
