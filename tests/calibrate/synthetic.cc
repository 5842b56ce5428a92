#include "synthetic.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

namespace mocap::test {

PinholeCamera Kinect1Camera() {
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = 525.3;
  camera.fy = 524.1;
  camera.cx = 319.2;
  camera.cy = 241.7;
  camera.dist = {0.16, -0.42, 0.0012, -0.0009, 0.25, 0, 0, 0};
  return camera;
}

BoardSpec TestBoard(BoardType type) {
  BoardSpec spec;
  spec.type = type;
  spec.squares_x = 8;
  spec.squares_y = 6;
  spec.square_m = 0.04;
  spec.marker_m = 0.03;
  spec.dictionary = "DICT_5X5_100";
  return spec;
}

BoardSpec LargeBoard() {
  BoardSpec spec = TestBoard();
  spec.squares_x = 12;
  spec.squares_y = 9;
  return spec;
}

Eigen::Quaterniond ExpSO3(const Eigen::Vector3d& rvec_rad) {
  const double angle = rvec_rad.norm();
  if (angle < 1e-15) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rvec_rad / angle));
}

Rigid3d Noisy(const Rigid3d& T, std::mt19937& rng, double sigma_m, double sigma_deg) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d dr = RadFromDeg(sigma_deg) * Eigen::Vector3d(n(rng), n(rng), n(rng));
  const Eigen::Vector3d dt = sigma_m * Eigen::Vector3d(n(rng), n(rng), n(rng));
  return Rigid3d(ExpSO3(dr) * T.rotation(), T.translation() + dt);
}

Rigid3d RandomBoardPose(std::mt19937& rng, const PinholeCamera& camera, const BoardSpec& spec, double min_z_m,
                        double max_z_m, double min_tilt_deg, double max_tilt_deg) {
  std::uniform_real_distribution<double> u(0, 1);
  const double z = min_z_m + (max_z_m - min_z_m) * u(rng);
  const Eigen::Vector2d pixel(camera.width * u(rng), camera.height * u(rng));
  const Eigen::Vector3d centre_camera = z * Eigen::Vector3d((pixel.x() - camera.cx) / camera.fx, (pixel.y() - camera.cy) / camera.fy, 1);
  // Facing the camera: board x = camera x, board y = -camera y, board z (out of the face) = -camera z.
  const Eigen::Quaterniond facing(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  const double tilt_axis = 2 * M_PI * u(rng), tilt = RadFromDeg(min_tilt_deg + (max_tilt_deg - min_tilt_deg) * u(rng));
  const Eigen::Quaterniond tilted(Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(tilt_axis), std::sin(tilt_axis), 0)));
  const Eigen::Quaterniond in_plane(Eigen::AngleAxisd(M_PI * (2 * u(rng) - 1), Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond R_camera_board = tilted * facing * in_plane;
  const Eigen::Vector3d centre_board(0.5 * spec.width_m(), 0.5 * spec.height_m(), 0);
  return Rigid3d(R_camera_board, centre_camera - R_camera_board * centre_board);
}

BoardDetection ProjectBoard(const PinholeCamera& camera, const BoardSpec& spec, const Rigid3d& T_camera_board,
                            double noise_px, std::mt19937& rng, int min_corners) {
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  std::vector<cv::Point3d> object;
  for (const Eigen::Vector3d& p : points_board) object.emplace_back(p.x(), p.y(), p.z());
  const Eigen::Vector3d r = T_camera_board.rvec(), t = T_camera_board.translation();
  const cv::Mat K = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat dist(1, 8, CV_64F, const_cast<double*>(camera.dist.data()));
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(r.x(), r.y(), r.z()), cv::Vec3d(t.x(), t.y(), t.z()), K, dist, image);
  std::normal_distribution<double> noise(0.0, noise_px);
  BoardDetection detection;
  for (size_t i = 0; i < image.size(); ++i) {
    const bool inside = image[i].x > 5 && image[i].y > 5 && image[i].x < camera.width - 6 && image[i].y < camera.height - 6;
    if (!inside || (T_camera_board * points_board[i]).z() <= 0.05) continue;
    detection.corner_ids.push_back(static_cast<int>(i));
    detection.corners_px.emplace_back(image[i].x + noise(rng), image[i].y + noise(rng));
  }
  if (static_cast<int>(detection.corner_ids.size()) < min_corners) detection.failure = "too few corners in view";
  return detection;
}

std::vector<Rigid3d> VisibleBoardPoses(std::mt19937& rng, const PinholeCamera& camera, const BoardSpec& spec, int count,
                                       double min_z_m, double max_z_m, double min_tilt_deg, double max_tilt_deg,
                                       int min_corners) {
  std::vector<Rigid3d> poses;
  std::mt19937 probe_rng(0);
  while (static_cast<int>(poses.size()) < count) {
    const Rigid3d T_camera_board = RandomBoardPose(rng, camera, spec, min_z_m, max_z_m, min_tilt_deg, max_tilt_deg);
    if (ProjectBoard(camera, spec, T_camera_board, 0.0, probe_rng, min_corners).found()) poses.push_back(T_camera_board);
  }
  return poses;
}

Eigen::Vector2d ProjectPlanar(const Eigen::Matrix3d& K, const Rigid3d& T_camera_board, const Eigen::Vector3d& p_board) {
  const Eigen::Vector3d p = K * (T_camera_board * p_board);
  return p.head<2>() / p.z();
}

cv::Mat RenderBoard(const BoardSpec& spec, const Eigen::Matrix3d& K, const Rigid3d& T_camera_board, cv::Size size) {
  const BoardImage board = DrawBoard(spec, 60, 30);
  const Eigen::Matrix3d R = T_camera_board.rotation_matrix();
  Eigen::Matrix3d plane;  // board plane z = 0: (x, y, 1) -> camera
  plane << R.col(0), R.col(1), T_camera_board.translation();
  constexpr int kSuper = 3;
  Eigen::Matrix3d S;  // output pixel -> supersampled pixel, centres aligned for INTER_AREA
  S << kSuper, 0, (kSuper - 1) / 2.0, 0, kSuper, (kSuper - 1) / 2.0, 0, 0, 1;
  const Eigen::Matrix3d H_super_texture = S * K * plane * board.H_pixel_board.inverse();
  cv::Matx33d H;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) H(r, c) = H_super_texture(r, c);
  cv::Mat super, image;
  cv::warpPerspective(board.gray, super, H, size * kSuper, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  cv::resize(super, image, size, 0, 0, cv::INTER_AREA);
  return image;
}

}  // namespace mocap::test
