#include "calibrate/camera_mount.h"

#include <gtest/gtest.h>

#include <cmath>
#include <tuple>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::ExpSO3;
using test::Kinect1Camera;
using test::TestBoard;

using test::kBoardbodyBoard;
using test::kCambodyCamera;

struct Noise {
  double corner_px = 0.2;
  double tracker_m = 0.15e-3;  ///< per axis
  double tracker_deg = 0.03;   ///< per axis: the largest error source (a 0.05 deg turn of the camera is 0.5 px)
};

/// Views of the board at the given poses in the camera; the camera body moves (board body fixed in the
/// tracker) or the board body moves (camera fixed).
std::vector<MountView> MakeViews(const std::vector<Rigid3d>& T_camera_board, bool camera_moves, const Noise& noise,
                                 std::mt19937& rng) {
  const Rigid3d fixed(ExpSO3(Eigen::Vector3d(0.3, 0.1, -0.2)), Eigen::Vector3d(0.5, 0.2, 1.0));
  std::vector<MountView> views;
  for (const Rigid3d& C : T_camera_board) {
    const Rigid3d A = camera_moves ? fixed * kBoardbodyBoard * C.inverse() * kCambodyCamera.inverse() : fixed;
    const Rigid3d B = camera_moves ? fixed : fixed * kCambodyCamera * C * kBoardbodyBoard.inverse();
    MountView view;
    view.T_tracker_cambody = test::Noisy(A, rng, noise.tracker_m, noise.tracker_deg);
    view.T_tracker_boardbody = test::Noisy(B, rng, noise.tracker_m, noise.tracker_deg);
    view.detection = test::ProjectBoard(Kinect1Camera(), TestBoard(), C, noise.corner_px, rng);
    views.push_back(view);
  }
  return views;
}

/// The recording the docs ask for: the board at 0.45-1.0 m, tilted 10-55 degrees, turned in its plane.
std::vector<Rigid3d> RandomPoses(std::mt19937& rng, int count) {
  return test::VisibleBoardPoses(rng, Kinect1Camera(), TestBoard(), count, 0.45, 1.0, 10, 55, 12);
}

/// The camera circles the board about the board's own y axis through its centre: one rotation axis.
std::vector<Rigid3d> OrbitPoses(std::mt19937& rng, int count) {
  const BoardSpec spec = TestBoard();
  const Eigen::Vector3d centre(0.5 * spec.width_m(), 0.5 * spec.height_m(), 0);
  const Eigen::Quaterniond facing(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  const Rigid3d C0(facing, Eigen::Vector3d(0, 0, 0.8) - facing * centre);
  std::uniform_real_distribution<double> angle(-RadFromDeg(35), RadFromDeg(35));
  std::vector<Rigid3d> poses;
  for (int i = 0; i < count; ++i) {
    const Rigid3d turn(Eigen::Quaterniond(Eigen::AngleAxisd(angle(rng), Eigen::Vector3d::UnitY())), Eigen::Vector3d::Zero());
    const Rigid3d to_centre(Eigen::Quaterniond::Identity(), centre);
    poses.push_back(C0 * to_centre * turn * to_centre.inverse());
  }
  return poses;
}

TEST(CameraMount, HandEyeMappingRecoversExactTransforms) {
  std::mt19937 rng(1);
  std::vector<Rigid3d> T_camera_board = RandomPoses(rng, 10), T_cambody_boardbody;
  for (const Rigid3d& C : T_camera_board) T_cambody_boardbody.push_back(kCambodyCamera * C * kBoardbodyBoard.inverse());
  const HandEyeMount mount = InitialiseMountHandEye(T_camera_board, T_cambody_boardbody);
  EXPECT_LT(TranslationDistanceM(mount.T_cambody_camera, kCambodyCamera), 1e-6);
  EXPECT_LT(RotationDistanceDeg(mount.T_cambody_camera, kCambodyCamera), 1e-4);
  EXPECT_LT(TranslationDistanceM(mount.T_boardbody_board, kBoardbodyBoard), 1e-6);
  EXPECT_LT(RotationDistanceDeg(mount.T_boardbody_board, kBoardbodyBoard), 1e-4);
}

class MountSeeds : public ::testing::TestWithParam<std::tuple<unsigned, bool>> {};

TEST_P(MountSeeds, RecoversBothMountsWithinAMillimetreAndATenthOfADegree) {
  const auto [seed, camera_moves] = GetParam();
  std::mt19937 rng(seed);
  const std::vector<MountView> views = MakeViews(RandomPoses(rng, 60), camera_moves, Noise{}, rng);
  const CameraMountResult result = CalibrateCameraMount(views, Kinect1Camera(), TestBoard());
  const double camera_mm = 1e3 * TranslationDistanceM(result.T_cambody_camera, kCambodyCamera);
  const double camera_deg = RotationDistanceDeg(result.T_cambody_camera, kCambodyCamera);
  const double board_mm = 1e3 * TranslationDistanceM(result.T_boardbody_board, kBoardbodyBoard);
  const double board_deg = RotationDistanceDeg(result.T_boardbody_board, kBoardbodyBoard);
  std::printf("seed %u %s: camera mount %.3f mm %.4f deg, board mount %.3f mm %.4f deg, rms %.3f -> %.3f px (%.3f mm), "
              "%d iterations, spread %.0f deg, axes %.0f deg\n", seed, camera_moves ? "camera moves" : "board moves",
              camera_mm, camera_deg, board_mm, board_deg, result.initial_rms_px, result.rms_px, result.rms_mm,
              result.iterations, result.rotation_spread_deg, result.axis_spread_deg);
  EXPECT_LT(camera_mm, 1.0);
  EXPECT_LT(camera_deg, 0.1);
  EXPECT_LT(board_mm, 1.0);
  EXPECT_LT(board_deg, 0.1);
  EXPECT_LE(result.rms_px, result.initial_rms_px);
  EXPECT_LT(result.rms_px, 1.0);
  EXPECT_GT(result.rms_mm, 0.0);
  EXPECT_EQ(result.views_used.size(), 60u);
  EXPECT_EQ(result.view_rms_px.size(), 60u);
  EXPECT_EQ(result.view_rms_mm.size(), 60u);
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
}

INSTANTIATE_TEST_SUITE_P(Seeds, MountSeeds, ::testing::Combine(::testing::Range(1u, 7u), ::testing::Bool()));

TEST(CameraMount, RejectsATrackerGlitchAndStaysAccurate) {
  std::mt19937 rng(4);
  std::vector<MountView> views = MakeViews(RandomPoses(rng, 60), true, Noise{}, rng);
  views[5].T_tracker_boardbody = Rigid3d(views[5].T_tracker_boardbody.rotation(),
                                         views[5].T_tracker_boardbody.translation() + Eigen::Vector3d(0.02, 0, 0));
  views[9].detection.failure = "no ArUco marker of DICT_5X5_100 found";
  const CameraMountResult result = CalibrateCameraMount(views, Kinect1Camera(), TestBoard());
  ASSERT_EQ(result.views_rejected.size(), 2u);
  EXPECT_EQ(result.views_rejected[0].index, 9);
  EXPECT_NE(result.views_rejected[0].reason.find("board not found"), std::string::npos);
  EXPECT_EQ(result.views_rejected[1].index, 5);
  EXPECT_NE(result.views_rejected[1].reason.find("after refinement"), std::string::npos) << result.views_rejected[1].reason;
  EXPECT_LT(TranslationDistanceM(result.T_cambody_camera, kCambodyCamera), 1e-3);
  EXPECT_LT(RotationDistanceDeg(result.T_cambody_camera, kCambodyCamera), 0.1);
}

TEST(CameraMount, WarnsWhenAllRotationsAreAboutOneAxis) {
  std::mt19937 rng(5);
  const std::vector<MountView> views = MakeViews(OrbitPoses(rng, 30), true, Noise{}, rng);
  const CameraMountResult result = CalibrateCameraMount(views, Kinect1Camera(), TestBoard());
  std::printf("orbit: spread %.1f deg, axes %.2f deg\n", result.rotation_spread_deg, result.axis_spread_deg);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_NE(result.warnings[0].find("about nearly one axis"), std::string::npos) << result.warnings[0];
  EXPECT_NE(result.warnings[0].find("rotate about a second axis"), std::string::npos) << result.warnings[0];
}

TEST(CameraMount, WarnsWhenTheBoardBarelyTurns) {
  std::mt19937 rng(6);
  const BoardSpec spec = TestBoard();
  const Eigen::Quaterniond facing(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Rigid3d> poses;
  for (int i = 0; i < 30; ++i) {
    const Eigen::Quaterniond R = ExpSO3(RadFromDeg(1.5) * Eigen::Vector3d(u(rng), u(rng), u(rng))) * facing;
    const Eigen::Vector3d centre(0.1 * u(rng), 0.08 * u(rng), 0.8 + 0.2 * u(rng));
    poses.emplace_back(R, centre - R * Eigen::Vector3d(0.5 * spec.width_m(), 0.5 * spec.height_m(), 0));
  }
  const CameraMountResult result = CalibrateCameraMount(MakeViews(poses, false, Noise{}, rng), Kinect1Camera(), spec);
  ASSERT_EQ(result.warnings.size(), 1u);
  EXPECT_NE(result.warnings[0].find("turn only"), std::string::npos) << result.warnings[0];
}

TEST(CameraMount, TooFewViewsSaysWhatToRecord) {
  std::mt19937 rng(7);
  std::vector<MountView> views = MakeViews(RandomPoses(rng, 9), true, Noise{}, rng);
  views[2].detection.failure = "no ArUco marker of DICT_5X5_100 found";
  views[4].detection.corner_ids.resize(3);
  views[4].detection.corners_px.resize(3);
  try {
    CalibrateCameraMount(views, Kinect1Camera(), TestBoard());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("too few usable views: 7 of 9 (need 8)"), std::string::npos) << what;
    EXPECT_NE(what.find("view 2: board not found"), std::string::npos) << what;
    EXPECT_NE(what.find("view 4: 3 corners detected (need 8)"), std::string::npos) << what;
  }
}

TEST(CameraMount, RefusesACheckerboard) {
  std::mt19937 rng(8);
  const std::vector<MountView> views = MakeViews(RandomPoses(rng, 10), true, Noise{}, rng);
  EXPECT_THROW(CalibrateCameraMount(views, Kinect1Camera(), TestBoard(BoardType::kCheckerboard)), InputError);
}

TEST(MotionSpread, MeasuresOneAxisAndTwoAxes) {
  std::vector<Rigid3d> one_axis, two_axes;
  for (int i = 0; i < 6; ++i) {
    one_axis.emplace_back(ExpSO3(RadFromDeg(10.0 * i) * Eigen::Vector3d::UnitZ()), Eigen::Vector3d::Zero());
    two_axes.emplace_back(ExpSO3(RadFromDeg(10.0 * i) * (i % 2 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX())),
                          Eigen::Vector3d::Zero());
  }
  const MotionSpread one = MeasureMotionSpread(one_axis), two = MeasureMotionSpread(two_axes);
  EXPECT_NEAR(one.rotation_spread_deg, 50.0, 1e-6);
  EXPECT_LT(one.axis_spread_deg, 1e-3);
  EXPECT_GT(two.axis_spread_deg, 30.0);
}

}  // namespace
}  // namespace mocap
