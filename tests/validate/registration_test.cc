// The registration seam (validate/registration.h): the acquisition's point-to-point ICP and the tracking
// step's point-to-plane step run through the registration the options name, and a null one is ours.
#include "validate/registration.h"

#include <gtest/gtest.h>

#include <atomic>
#include <random>

#include "synthetic.h"
#include "validate/tracker.h"

namespace mocap {
namespace {

/// Ours, counting its calls.
class CountingRegistration final : public Registration {
 public:
  std::string_view name() const override { return "counting"; }
  IcpResult PointToPoint(const PointCloud& source, const PointGrid& scene, const Rigid3d& T_init,
                         const IcpOptions& options) const override {
    ++point_to_point;
    return own_.PointToPoint(source, scene, T_init, options);
  }
  IcpResult PointToPlane(const ModelCrop& crop, const PointGrid& scene, const Rigid3d& T_init,
                         const ObservabilityOptions& options, double first_gate_m, PlaneRefinement* refinement) const override {
    ++point_to_plane;
    return own_.PointToPlane(crop, scene, T_init, options, first_gate_m, refinement);
  }
  mutable std::atomic<int> point_to_point{0}, point_to_plane{0};

 private:
  SegIcpRegistration own_;
};


/// The box's surface seen by a camera 0.8 m away, with 1 mm noise (camera frame).
PointCloud SceneOf(const Rigid3d& T_camera_object, uint32_t seed) {
  const SurfaceCropSource sensor = SurfaceCropSource::FromMesh(testing::BoxMesh({0.16, 0.06, 0.21}), CropOptions{.pixel_m = 0.002});
  std::mt19937 rng(seed);
  return testing::AddNoise(Transform(T_camera_object, sensor.Crop(T_camera_object).points_model), rng, 0.001);
}

TEST(Registration, AcquisitionRegistersEveryHypothesisThroughTheGivenOneAndNullIsOurs) {
  const SurfaceCropSource model = SurfaceCropSource::FromMesh(testing::BoxMesh({0.16, 0.06, 0.21}), CropOptions{});
  const Rigid3d T_camera_object = Rigid3d::FromRvec({0.3, -0.2, 0.1}, {0.02, -0.01, 0.8});
  const PointCloud scene = SceneOf(T_camera_object, 1);
  const PointGrid grid(scene);
  const Rigid3d prior = T_camera_object * Rigid3d::FromRvec({0.0, 0.05, 0.0}, {0.005, 0.0, 0.0});
  AcquisitionOptions options;
  const AcquisitionResult own = AcquireAround(scene, grid, model, prior, options, AlignmentOptions{});
  const auto counting = std::make_shared<CountingRegistration>();
  options.registration = counting;
  const AcquisitionResult counted = AcquireAround(scene, grid, model, prior, options, AlignmentOptions{});
  // Every hypothesis in the coarse stage, then the refined ones.
  EXPECT_EQ(counting->point_to_point.load(), static_cast<int>(counted.hypotheses.size()) + options.refine_count);
  EXPECT_EQ(counting->point_to_plane.load(), 0);
  ASSERT_TRUE(own.acquired);
  EXPECT_TRUE(counted.T_camera_model.matrix4() == own.T_camera_model.matrix4());
  EXPECT_EQ(counted.score, own.score);
  EXPECT_LT(TranslationDistanceM(own.T_camera_model, T_camera_object), 0.003);
}

TEST(Registration, TrackingStepIsThePointToPlaneCall) {
  const SurfaceCropSource model = SurfaceCropSource::FromMesh(testing::BoxMesh({0.16, 0.06, 0.21}), CropOptions{});
  ValidateOptions options;
  const auto counting = std::make_shared<CountingRegistration>();
  options.acquisition.registration = counting;
  ObjectTracker tracker(model, options);
  for (int k = 0; k < 3; ++k) {
    const Rigid3d T_camera_object = Rigid3d::FromRvec({0.3, -0.2, 0.1 + 0.01 * k}, {0.02 + 0.002 * k, -0.01, 0.8});
    const TrackStep step = tracker.Step(SceneOf(T_camera_object, 2 + k), Rigid3d(), k * 33'333'333LL, &T_camera_object);
    ASSERT_TRUE(step.measured) << "frame " << k << ": " << step.note;
    EXPECT_EQ(step.mode, k == 0 ? TrackMode::kAcquisition : TrackMode::kTracking) << "frame " << k;
    EXPECT_EQ(counting->point_to_plane.load(), k) << "frame " << k;
    // A step from the filter's prediction, not a converged estimate: within a centimetre (what this
    // test asks is which registration ran).
    EXPECT_LT(TranslationDistanceM(step.T_camera_object_measured, T_camera_object), 0.01) << "frame " << k;
  }
}

}  // namespace
}  // namespace mocap
