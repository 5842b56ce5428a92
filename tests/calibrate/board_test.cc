#include "calibrate/board.h"

#include <gtest/gtest.h>
#include <opencv2/aruco/charuco.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "calibrate/board_pose.h"
#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::RenderBoard;
using test::TestBoard;

Eigen::Matrix3d IdealK() {
  Eigen::Matrix3d K;
  K << 525.0, 0, 319.5, 0, 525.0, 239.5, 0, 0, 1;
  return K;
}

/// Views of the board at 0.45-0.8 m, tilted up to 40 degrees, wholly inside a 640x480 image.
std::vector<Rigid3d> RenderablePoses(BoardType type, int count, unsigned seed) {
  std::mt19937 rng(seed);
  PinholeCamera ideal = test::Kinect1Camera();
  ideal.fx = ideal.fy = 525.0;
  ideal.cx = 319.5;
  ideal.cy = 239.5;
  ideal.dist = {};
  const BoardSpec spec = TestBoard(type);
  return test::VisibleBoardPoses(rng, ideal, spec, count, 0.45, 0.8, 0.0, 40.0, spec.corner_count());
}

std::string CheckMessage(const BoardSpec& spec) {
  try {
    spec.check();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(BoardSpec, CheckNamesTheField) {
  BoardSpec spec = TestBoard();
  EXPECT_EQ(CheckMessage(spec), "");
  spec.squares_x = 2;
  EXPECT_NE(CheckMessage(spec).find("board.squares_x"), std::string::npos);
  spec = TestBoard();
  spec.marker_m = spec.square_m;
  EXPECT_NE(CheckMessage(spec).find("board.marker_m"), std::string::npos);
  spec = TestBoard();
  spec.square_m = 40;  // millimetres by mistake
  EXPECT_NE(CheckMessage(spec).find("board.square_m"), std::string::npos);
  spec = TestBoard();
  spec.dictionary = "DICT_5X5_42";
  EXPECT_NE(CheckMessage(spec).find("board.dictionary"), std::string::npos);
  spec = TestBoard();
  spec.dictionary = "DICT_4X4_50";
  spec.squares_x = 12;
  spec.squares_y = 10;  // 60 markers needed
  EXPECT_NE(CheckMessage(spec).find("holds 50 markers"), std::string::npos);
  EXPECT_THROW(BoardTypeFromString("circles"), InputError);
}

TEST(BoardCornerPoints, MatchOpenCvCharucoCornersTurnedAboutX) {
  const BoardSpec spec = TestBoard();
  const std::vector<Eigen::Vector3d> ours = BoardCornerPoints(spec);
  const cv::Ptr<cv::aruco::CharucoBoard> board = MakeCharucoBoard(spec);
  ASSERT_EQ(ours.size(), board->chessboardCorners.size());
  for (size_t i = 0; i < ours.size(); ++i) {
    const cv::Point3f& p = board->chessboardCorners[i];
    EXPECT_NEAR(ours[i].x(), p.x, 1e-6) << i;
    EXPECT_NEAR(ours[i].y(), spec.height_m() - p.y, 1e-6) << i;
    EXPECT_EQ(ours[i].z(), 0.0);
  }
  // Corner 0 is the top-left inner corner of the upright board; the origin its bottom-left outer corner.
  EXPECT_NEAR(ours[0].x(), 0.04, 1e-12);
  EXPECT_NEAR(ours[0].y(), 0.20, 1e-12);
}

TEST(DrawBoard, MapsTheBoardFrameOntoItsPixels) {
  const BoardSpec spec = TestBoard();
  const BoardImage image = DrawBoard(spec, 50, 20);
  EXPECT_EQ(image.gray.cols, 8 * 50 + 40);
  EXPECT_EQ(image.gray.rows, 6 * 50 + 40);
  // The top-left square is black: its centre (x = 0.02, y = 0.22) must fall on a black pixel.
  const Eigen::Vector3d top_left = image.H_pixel_board * Eigen::Vector3d(0.02, 0.22, 1);
  EXPECT_NEAR(top_left.x(), 20 - 0.5 + 25, 1e-9);
  EXPECT_NEAR(top_left.y(), 20 - 0.5 + 25, 1e-9);
  EXPECT_EQ(image.gray.at<uint8_t>(44, 44), 0);
  EXPECT_EQ(image.gray.at<uint8_t>(5, 5), 255);  // margin
  EXPECT_THROW(DrawBoard(spec, 4, 0), InputError);
}

TEST(DetectBoard, FindsRenderedCharucoCornersWithinHalfAPixel) {
  const BoardSpec spec = TestBoard();
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  double worst_px = 0, sum_px = 0;
  int count = 0, views = 0;
  for (const Rigid3d& T_camera_board : RenderablePoses(BoardType::kCharuco, 8, 11)) {
    const cv::Mat image = RenderBoard(spec, IdealK(), T_camera_board, cv::Size(640, 480));
    const BoardDetection detection = DetectBoard(image, spec);
    ASSERT_TRUE(detection.found()) << detection.failure;
    // A few small, strongly tilted markers may stay undecoded; each corner needs its two markers.
    EXPECT_GE(detection.corner_ids.size(), 3 * points_board.size() / 4);
    ++views;
    for (size_t i = 0; i < detection.corner_ids.size(); ++i) {
      const Eigen::Vector2d truth = test::ProjectPlanar(IdealK(), T_camera_board, points_board[detection.corner_ids[i]]);
      const double error = (detection.corners_px[i] - truth).norm();
      worst_px = std::max(worst_px, error);
      sum_px += error;
      ++count;
    }
  }
  std::printf("ChArUco corners: %d of %d found, mean error %.3f px, worst %.3f px\n", count,
              views * static_cast<int>(points_board.size()), sum_px / count, worst_px);
  EXPECT_LT(worst_px, 0.5);
  EXPECT_LT(sum_px / count, 0.15);
}

TEST(DetectBoard, PoseFromRenderedCharucoMatchesTruth) {
  const BoardSpec spec = TestBoard();
  PinholeCamera ideal;
  ideal.width = 640, ideal.height = 480, ideal.fx = ideal.fy = 525.0, ideal.cx = 319.5, ideal.cy = 239.5;
  for (const Rigid3d& T_camera_board : RenderablePoses(BoardType::kCharuco, 4, 12)) {
    const BoardDetection detection = DetectBoard(RenderBoard(spec, IdealK(), T_camera_board, cv::Size(640, 480)), spec);
    const std::optional<BoardPose> pose = EstimateBoardPose(detection, spec, ideal);
    ASSERT_TRUE(pose.has_value());
    EXPECT_LT(RotationDistanceDeg(pose->T_camera_board, T_camera_board), 0.5);
    EXPECT_LT(TranslationDistanceM(pose->T_camera_board, T_camera_board), 0.005);
    EXPECT_LT(pose->rms_px, 0.3);
  }
}

TEST(DetectBoard, FindsRenderedCheckerboardWithinHalfAPixel) {
  const BoardSpec spec = TestBoard(BoardType::kCheckerboard);
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  const int n = spec.corner_count();
  double worst_px = 0;
  for (const Rigid3d& T_camera_board : RenderablePoses(BoardType::kCheckerboard, 4, 13)) {
    const BoardDetection detection = DetectBoard(RenderBoard(spec, IdealK(), T_camera_board, cv::Size(640, 480)), spec);
    ASSERT_TRUE(detection.found()) << detection.failure;
    ASSERT_EQ(static_cast<int>(detection.corner_ids.size()), n);
    // The order can start at either end (a half turn of a symmetric pattern): take the closer one.
    double forward = 0, reverse = 0;
    for (int i = 0; i < n; ++i) {
      forward = std::max(forward, (detection.corners_px[i] - test::ProjectPlanar(IdealK(), T_camera_board, points_board[i])).norm());
      reverse = std::max(reverse, (detection.corners_px[i] - test::ProjectPlanar(IdealK(), T_camera_board, points_board[n - 1 - i])).norm());
    }
    worst_px = std::max(worst_px, std::min(forward, reverse));
  }
  std::printf("checkerboard corners: worst %.3f px\n", worst_px);
  EXPECT_LT(worst_px, 0.5);
}

TEST(DetectBoard, SaysWhyNothingWasFound) {
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  const BoardDetection charuco = DetectBoard(blank, TestBoard());
  EXPECT_FALSE(charuco.found());
  EXPECT_NE(charuco.failure.find("no ArUco marker of DICT_5X5_100"), std::string::npos) << charuco.failure;
  const BoardDetection checker = DetectBoard(blank, TestBoard(BoardType::kCheckerboard));
  EXPECT_NE(checker.failure.find("no checkerboard of 7x5"), std::string::npos) << checker.failure;
  EXPECT_THROW(DetectBoard(cv::Mat(), TestBoard()), InputError);
  EXPECT_THROW(DetectBoard(cv::Mat(480, 640, CV_32FC1, cv::Scalar(0)), TestBoard()), InputError);
}

TEST(DetectBoard, ReportsTooFewCornersOfAMostlyHiddenBoard) {
  const BoardSpec spec = TestBoard();
  const Rigid3d T_camera_board = RenderablePoses(BoardType::kCharuco, 1, 14)[0];
  cv::Mat image = RenderBoard(spec, IdealK(), T_camera_board, cv::Size(640, 480));
  const BoardDetection whole = DetectBoard(image, spec);
  ASSERT_TRUE(whole.found());
  // Cover all but a corner of the board: a few markers remain, too few corners for min_corners 20.
  const Eigen::Vector2d keep = test::ProjectPlanar(IdealK(), T_camera_board, BoardCornerPoints(spec)[0]);
  cv::Mat mask(image.size(), CV_8UC1, cv::Scalar(255));
  cv::circle(mask, cv::Point(static_cast<int>(keep.x()), static_cast<int>(keep.y())), 60, cv::Scalar(0), cv::FILLED);
  image.setTo(cv::Scalar(128), mask);
  const BoardDetection partial = DetectBoard(image, spec, 20);
  EXPECT_FALSE(partial.found());
  EXPECT_NE(partial.failure.find("(need 20)"), std::string::npos) << partial.failure;
}

}  // namespace
}  // namespace mocap
