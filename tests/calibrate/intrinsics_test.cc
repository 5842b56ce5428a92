#include "calibrate/intrinsics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::Kinect1Camera;
using test::LargeBoard;
using test::TestBoard;

/// The recording the docs ask for: a 0.48 x 0.36 m board at 0.45-0.85 m (half the image wide or more),
/// tilted 20-55 degrees towards the camera, over the whole image (at least half its corners in view).
std::vector<BoardDetection> SyntheticViews(unsigned seed, int count, double noise_px) {
  std::mt19937 rng(seed);
  const PinholeCamera camera = Kinect1Camera();
  const BoardSpec spec = LargeBoard();
  std::vector<BoardDetection> views;
  for (const Rigid3d& T_camera_board :
       test::VisibleBoardPoses(rng, camera, spec, count, 0.45, 0.85, 20, 55, spec.corner_count() / 2))
    views.push_back(test::ProjectBoard(camera, spec, T_camera_board, noise_px, rng));
  return views;
}

/// Largest pixel distance between the two cameras' projections of rays through a grid over the image.
double MaxProjectionDifferencePx(const PinholeCamera& truth, const PinholeCamera& estimate) {
  double worst = 0;
  for (int v = 20; v < truth.height; v += 40)
    for (int u = 20; u < truth.width; u += 40) {
      const Eigen::Vector3d ray = truth.Ray(Eigen::Vector2d(u, v));
      worst = std::max(worst, (*estimate.Project(ray) - Eigen::Vector2d(u, v)).norm());
    }
  return worst;
}

class IntrinsicsSeeds : public ::testing::TestWithParam<unsigned> {};

TEST_P(IntrinsicsSeeds, RecoversKinect1CameraFromSixtyNoisyViews) {
  const std::vector<BoardDetection> views = SyntheticViews(GetParam(), 60, 0.2);
  const IntrinsicsResult result = CalibrateIntrinsics(views, cv::Size(640, 480), LargeBoard());
  const PinholeCamera truth = Kinect1Camera();
  const PinholeCamera& c = result.camera;
  std::printf("seed %u: fx %+.3f%% fy %+.3f%% cx %+.3f px cy %+.3f px (1-sigma %.3f%% %.2f px), rms %.3f px, coverage "
              "%.2f, max reprojection difference %.3f px\n", GetParam(), 100 * (c.fx / truth.fx - 1),
              100 * (c.fy / truth.fy - 1), c.cx - truth.cx, c.cy - truth.cy, 100 * result.fx_std_px / c.fx,
              result.cx_std_px, result.rms_px, result.coverage, MaxProjectionDifferencePx(truth, c));
  EXPECT_NEAR(c.fx / truth.fx, 1.0, 0.002);
  EXPECT_NEAR(c.fy / truth.fy, 1.0, 0.002);
  EXPECT_NEAR(c.cx, truth.cx, 1.0);
  EXPECT_NEAR(c.cy, truth.cy, 1.0);
  EXPECT_LT(MaxProjectionDifferencePx(truth, c), 1.0);  // to the image corners, where k3 extrapolates
  EXPECT_NEAR(result.rms_px, 0.2 * std::sqrt(2.0), 0.05);  // the noise put in, per corner
  EXPECT_EQ(result.views_used.size(), 60u);
  EXPECT_EQ(result.view_rms_px.size(), 60u);
  EXPECT_TRUE(result.views_rejected.empty());
  EXPECT_GT(result.coverage, 0.8);
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  EXPECT_GT(result.fx_std_px, 0.0);
  EXPECT_LT(result.fx_std_px, 1.0);
}

INSTANTIATE_TEST_SUITE_P(Seeds, IntrinsicsSeeds, ::testing::Range(1u, 7u));

TEST(Intrinsics, RejectsViewsNotFoundAndOutliersWithReasons) {
  std::vector<BoardDetection> views = SyntheticViews(5, 50, 0.2);
  views[3] = BoardDetection{};
  views[3].failure = "no ArUco marker of DICT_5X5_100 found";
  views[7].corner_ids.resize(5);
  views[7].corners_px.resize(5);
  for (size_t k = 0; k < views[11].corners_px.size(); k += 3) views[11].corners_px[k] += Eigen::Vector2d(4.0, -3.0);
  const IntrinsicsResult result = CalibrateIntrinsics(views, cv::Size(640, 480), LargeBoard());
  ASSERT_EQ(result.views_rejected.size(), 3u);
  EXPECT_EQ(result.views_rejected[0].index, 3);
  EXPECT_NE(result.views_rejected[0].reason.find("board not found: no ArUco marker"), std::string::npos);
  EXPECT_EQ(result.views_rejected[1].index, 7);
  EXPECT_NE(result.views_rejected[1].reason.find("5 corners detected (need 8)"), std::string::npos);
  EXPECT_EQ(result.views_rejected[2].index, 11);
  EXPECT_NE(result.views_rejected[2].reason.find("reprojection RMS"), std::string::npos);
  EXPECT_EQ(result.views_used.size(), 47u);
  EXPECT_NEAR(result.camera.fx / Kinect1Camera().fx, 1.0, 0.002);
}

TEST(Intrinsics, TooFewViewsSaysWhatToRecord) {
  const std::vector<BoardDetection> views = SyntheticViews(6, 6, 0.2);
  try {
    CalibrateIntrinsics(views, cv::Size(640, 480), LargeBoard());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("too few usable views: 6 of 6 (need 10)"), std::string::npos) << what;
    EXPECT_NE(what.find("record the board in more positions"), std::string::npos) << what;
  }
}

TEST(Intrinsics, WarnsWhenTheBoardStaysInTheImageCentre) {
  // Far away and small: the corners cover only the middle of the image.
  std::mt19937 rng(7);
  const PinholeCamera camera = Kinect1Camera();
  std::vector<BoardDetection> views;
  PinholeCamera centre = camera;
  centre.width = 200, centre.height = 150, centre.cx = 100, centre.cy = 75;  // draw poses for the centre only
  for (const Rigid3d& T_camera_board : test::VisibleBoardPoses(rng, centre, TestBoard(), 20, 1.6, 2.0, 0, 30, 35))
    views.push_back(test::ProjectBoard(camera, TestBoard(), T_camera_board, 0.2, rng));
  const IntrinsicsResult result = CalibrateIntrinsics(views, cv::Size(640, 480), TestBoard());
  EXPECT_LT(result.coverage, 0.6);
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_NE(result.warnings.front().find("the corners cover only"), std::string::npos) << result.warnings.front();
}

TEST(Intrinsics, DistortionModelChoosesTheCoefficients) {
  const std::vector<BoardDetection> views = SyntheticViews(8, 30, 0.2);
  IntrinsicsOptions options;
  options.model = DistortionModel::kK1K2P1P2;
  const IntrinsicsResult fixed_k3 = CalibrateIntrinsics(views, cv::Size(640, 480), LargeBoard(), options);
  EXPECT_EQ(fixed_k3.camera.dist[4], 0.0);
  EXPECT_NE(fixed_k3.camera.dist[0], 0.0);
  options.model = DistortionModel::kRational;
  const IntrinsicsResult rational = CalibrateIntrinsics(views, cv::Size(640, 480), LargeBoard(), options);
  EXPECT_TRUE(rational.camera.dist[5] != 0.0 || rational.camera.dist[6] != 0.0 || rational.camera.dist[7] != 0.0);
  EXPECT_NEAR(rational.rms_px, 0.2 * std::sqrt(2.0), 0.05);
}

TEST(IntrinsicsOptions, CheckNamesTheField) {
  IntrinsicsOptions options;
  options.min_views = 1;
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.max_view_rms_px = 0;
  try {
    options.check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("max_view_rms_px"), std::string::npos);
  }
}

}  // namespace
}  // namespace mocap
