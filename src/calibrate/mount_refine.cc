#include "calibrate/mount_refine.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>

namespace mocap {
namespace {

using Pose6 = std::array<double, 6>;  // angle-axis (rad), translation (m)

Pose6 ToPose6(const Rigid3d& T) {
  const Eigen::Vector3d r = T.rvec();
  return {r.x(), r.y(), r.z(), T.translation().x(), T.translation().y(), T.translation().z()};
}

Rigid3d FromPose6(const Pose6& p) {
  return Rigid3d::FromRvec(Eigen::Vector3d(p[0], p[1], p[2]), Eigen::Vector3d(p[3], p[4], p[5]));
}

/// OpenCV's projection (calib3d "Detailed description"), templated for automatic differentiation.
template <typename T>
bool ProjectOpenCv(const PinholeCamera& c, const T* p_camera, T* uv) {
  if (!(p_camera[2] > T(0))) return false;
  const auto& [k1, k2, p1, p2, k3, k4, k5, k6] = c.dist;
  const T x = p_camera[0] / p_camera[2], y = p_camera[1] / p_camera[2];
  const T r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const T radial = (1.0 + k1 * r2 + k2 * r4 + k3 * r6) / (1.0 + k4 * r2 + k5 * r4 + k6 * r6);
  const T xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
  const T yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
  uv[0] = c.fx * xd + c.cx;
  uv[1] = c.fy * yd + c.cy;
  return true;
}

/// Residual of one corner: its detected pixel minus the projection of
/// inv(T_cambody_camera) * T_cambody_boardbody * T_boardbody_board * p_board.
struct CornerCost {
  CornerCost(const PinholeCamera& camera, const Rigid3d& T_cambody_boardbody, const Eigen::Vector3d& p_board,
             const Eigen::Vector2d& uv_px)
      : camera_(camera), R_cambody_boardbody_(T_cambody_boardbody.rotation_matrix()),
        t_cambody_boardbody_(T_cambody_boardbody.translation()), p_board_(p_board), uv_px_(uv_px) {}

  template <typename T>
  bool operator()(const T* cambody_camera, const T* boardbody_board, T* residual) const {
    const T p_board[3] = {T(p_board_.x()), T(p_board_.y()), T(p_board_.z())};
    T p_boardbody[3];
    ceres::AngleAxisRotatePoint(boardbody_board, p_board, p_boardbody);
    for (int i = 0; i < 3; ++i) p_boardbody[i] += boardbody_board[3 + i];
    T d_cambody[3];
    for (int r = 0; r < 3; ++r) {
      d_cambody[r] = T(t_cambody_boardbody_(r)) - cambody_camera[3 + r];
      for (int c = 0; c < 3; ++c) d_cambody[r] += R_cambody_boardbody_(r, c) * p_boardbody[c];
    }
    const T minus_rvec[3] = {-cambody_camera[0], -cambody_camera[1], -cambody_camera[2]};
    T p_camera[3], uv[2];
    ceres::AngleAxisRotatePoint(minus_rvec, d_cambody, p_camera);
    if (!ProjectOpenCv(camera_, p_camera, uv)) return false;
    residual[0] = uv[0] - uv_px_.x();
    residual[1] = uv[1] - uv_px_.y();
    return true;
  }

  PinholeCamera camera_;
  Eigen::Matrix3d R_cambody_boardbody_;
  Eigen::Vector3d t_cambody_boardbody_, p_board_;
  Eigen::Vector2d uv_px_;
};

}  // namespace

Rigid3d ChainCameraBoard(const MountChainView& view, const MountEstimate& mount) {
  return mount.T_cambody_camera.inverse() * view.T_cambody_boardbody * mount.T_boardbody_board;
}

MountEstimate RefineMount(const std::vector<MountChainView>& views, const std::vector<Eigen::Vector3d>& points_board,
                          const PinholeCamera& camera, const MountEstimate& initial, double huber_px, int max_iterations) {
  Pose6 cambody_camera = ToPose6(initial.T_cambody_camera), boardbody_board = ToPose6(initial.T_boardbody_board);
  ceres::Problem problem;
  for (const MountChainView& view : views)
    for (size_t k = 0; k < view.detection->corner_ids.size(); ++k) {
      const Eigen::Vector3d& p_board = points_board[static_cast<size_t>(view.detection->corner_ids[k])];
      auto* cost = new ceres::AutoDiffCostFunction<CornerCost, 2, 6, 6>(
          new CornerCost(camera, view.T_cambody_boardbody, p_board, view.detection->corners_px[k]));
      problem.AddResidualBlock(cost, new ceres::HuberLoss(huber_px), cambody_camera.data(), boardbody_board.data());
    }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  MountEstimate out;
  out.T_cambody_camera = FromPose6(cambody_camera);
  out.T_boardbody_board = FromPose6(boardbody_board);
  out.iterations = static_cast<int>(summary.iterations.size());
  return out;
}

}  // namespace mocap
