#pragma once
// Ceres refinement of the camera mount (internal to src/calibrate): both unknown transforms as 6-DoF
// (angle-axis, translation), every detected corner of every view one robust residual.
#include <Eigen/Core>
#include <vector>

#include "calibrate/board.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap {

/// One view of the problem: the tracked relative pose inv(T_tracker_cambody) * T_tracker_boardbody and
/// the board corners seen. The detection must outlive the call.
struct MountChainView {
  Rigid3d T_cambody_boardbody;
  const BoardDetection* detection = nullptr;
};

struct MountEstimate {
  Rigid3d T_cambody_camera;
  Rigid3d T_boardbody_board;
  int iterations = 0;
};

/// T_camera_board of one view through the chain.
Rigid3d ChainCameraBoard(const MountChainView& view, const MountEstimate& mount);

/// Minimises sum_i sum_k rho(|project(T_camera_board_i * p_k) - u_ik|^2) with a Huber rho of scale
/// huber_px, starting from `initial`. Intrinsics fixed.
MountEstimate RefineMount(const std::vector<MountChainView>& views, const std::vector<Eigen::Vector3d>& points_board,
                          const PinholeCamera& camera, const MountEstimate& initial, double huber_px, int max_iterations);

}  // namespace mocap
