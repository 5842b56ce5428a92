#include "calibrate/camera_mount.h"

#include <opencv2/calib3d.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "calibrate/board_pose.h"
#include "calibrate/cv_convert.h"
#include "calibrate/mount_refine.h"
#include "core/check.h"

namespace mocap {
namespace {

struct PreparedView {
  int index = 0;
  MountChainView chain;
  Rigid3d T_camera_board;  ///< from the view's own solvePnP
};

/// Empty reason and a prepared view, or why the view cannot be used.
std::string PrepareView(const MountView& view, const PinholeCamera& camera, const BoardSpec& spec,
                        const CameraMountOptions& options, PreparedView& out) {
  if (!view.detection.found()) return "board not found: " + view.detection.failure;
  const int corners = static_cast<int>(view.detection.corner_ids.size());
  if (corners < options.min_corners_per_view) return Str(corners, " corners detected (need ", options.min_corners_per_view, ")");
  const std::optional<BoardPose> pose = EstimateBoardPose(view.detection, spec, camera);
  if (!pose) return "no board pose from the corners (solvePnP failed)";
  if (pose->rms_px > options.max_pnp_rms_px)
    return Str("the board's own pose fits its corners to ", pose->rms_px, " px > ", options.max_pnp_rms_px,
               " px: wrong intrinsics, motion blur or a bent board");
  out.chain.T_cambody_boardbody = view.T_tracker_cambody.inverse() * view.T_tracker_boardbody;
  out.chain.detection = &view.detection;
  out.T_camera_board = pose->T_camera_board;
  return "";
}

void RequireViews(size_t usable, size_t total, const CameraMountOptions& options, const std::vector<RejectedView>& rejected) {
  if (static_cast<int>(usable) >= options.min_views) return;
  std::string why;
  for (size_t i = 0; i < rejected.size() && i < 5; ++i) why += Str("; view ", rejected[i].index, ": ", rejected[i].reason);
  if (rejected.size() > 5) why += Str("; and ", rejected.size() - 5, " more");
  throw InputError("camera-mount", Str("too few usable views: ", usable, " of ", total, " (need ", options.min_views,
                                       "); record the board filling a good part of the image from more positions, "
                                       "rotating board or camera about two different axes", why));
}

MountEstimate HandEyeInitialisation(const std::vector<PreparedView>& views) {
  std::vector<Rigid3d> T_camera_board, T_cambody_boardbody;
  for (const PreparedView& v : views) {
    T_camera_board.push_back(v.T_camera_board);
    T_cambody_boardbody.push_back(v.chain.T_cambody_boardbody);
  }
  const HandEyeMount mount = InitialiseMountHandEye(T_camera_board, T_cambody_boardbody);
  return {mount.T_cambody_camera, mount.T_boardbody_board, 0};
}

struct ViewResiduals {
  std::vector<double> rms_px, rms_mm;
  double total_rms_px = 0, total_rms_mm = 0;
};

ViewResiduals Residuals(const std::vector<PreparedView>& views, const std::vector<Eigen::Vector3d>& points_board,
                        const PinholeCamera& camera, const MountEstimate& mount) {
  ViewResiduals out;
  double sum_px2 = 0, sum_mm2 = 0;
  size_t count = 0;
  const double focal_px = 0.5 * (camera.fx + camera.fy);
  for (const PreparedView& v : views) {
    const Rigid3d T_camera_board = ChainCameraBoard(v.chain, mount);
    const std::vector<Eigen::Vector2d> errors = ReprojectionErrorsPx(*v.chain.detection, points_board, camera, T_camera_board);
    double view_px2 = 0, view_mm2 = 0;
    for (size_t k = 0; k < errors.size(); ++k) {
      const double depth_m = (T_camera_board * points_board[static_cast<size_t>(v.chain.detection->corner_ids[k])]).z();
      view_px2 += errors[k].squaredNorm();
      view_mm2 += std::pow(errors[k].norm() * depth_m / focal_px * 1e3, 2);
    }
    out.rms_px.push_back(std::sqrt(view_px2 / static_cast<double>(errors.size())));
    out.rms_mm.push_back(std::sqrt(view_mm2 / static_cast<double>(errors.size())));
    sum_px2 += view_px2;
    sum_mm2 += view_mm2;
    count += errors.size();
  }
  out.total_rms_px = std::sqrt(sum_px2 / static_cast<double>(std::max<size_t>(count, 1)));
  out.total_rms_mm = std::sqrt(sum_mm2 / static_cast<double>(std::max<size_t>(count, 1)));
  return out;
}

void AddMotionWarnings(const CameraMountOptions& options, CameraMountResult& result) {
  if (result.rotation_spread_deg < options.min_rotation_spread_deg)
    result.warnings.push_back(Str("degenerate motion: camera and board turn only ", result.rotation_spread_deg,
                                  " degrees relative to each other over all views; rotate the board (or camera) by "
                                  "30 degrees or more about two different axes (tilt left-right and up-down)"));
  else if (result.axis_spread_deg < options.min_axis_spread_deg)
    result.warnings.push_back(Str("degenerate motion: all relative rotations are about nearly one axis (axes within ",
                                  result.axis_spread_deg, " degrees); the mounts are not fully observable (a shift "
                                  "along that axis is not): also rotate about a second axis, e.g. pitch as well as yaw"));
}

/// Drops views whose refined RMS exceeds the limit; true when any was dropped.
bool RejectBadViews(const CameraMountOptions& options, const ViewResiduals& residuals, std::vector<PreparedView>& views,
                    std::vector<RejectedView>& rejected) {
  std::vector<PreparedView> kept;
  for (size_t i = 0; i < views.size(); ++i) {
    if (residuals.rms_px[i] <= options.max_view_rms_px) kept.push_back(views[i]);
    else rejected.push_back({views[i].index, Str("reprojection RMS ", residuals.rms_px[i], " px > ", options.max_view_rms_px,
                                                 " px after refinement: a tracker glitch, a stale pose or a moved marker")});
  }
  const bool dropped = kept.size() != views.size();
  views = std::move(kept);
  return dropped;
}

std::vector<PreparedView> PrepareViews(std::span<const MountView> views, const PinholeCamera& camera,
                                       const BoardSpec& spec, const CameraMountOptions& options,
                                       std::vector<RejectedView>& rejected) {
  std::vector<PreparedView> prepared;
  for (size_t i = 0; i < views.size(); ++i) {
    PreparedView v;
    v.index = static_cast<int>(i);
    std::string reason = PrepareView(views[i], camera, spec, options, v);
    if (reason.empty()) prepared.push_back(v);
    else rejected.push_back({v.index, std::move(reason)});
  }
  return prepared;
}

std::vector<MountChainView> Chain(const std::vector<PreparedView>& views) {
  std::vector<MountChainView> chain;
  for (const PreparedView& v : views) chain.push_back(v.chain);
  return chain;
}

void FillResult(const std::vector<PreparedView>& views, const std::vector<Eigen::Vector3d>& points_board,
                const PinholeCamera& camera, const MountEstimate& mount, CameraMountResult& result) {
  const ViewResiduals residuals = Residuals(views, points_board, camera, mount);
  result.T_cambody_camera = mount.T_cambody_camera;
  result.T_boardbody_board = mount.T_boardbody_board;
  result.iterations = mount.iterations;
  result.rms_px = residuals.total_rms_px;
  result.rms_mm = residuals.total_rms_mm;
  result.view_rms_px = residuals.rms_px;
  result.view_rms_mm = residuals.rms_mm;
  std::vector<Rigid3d> relative;
  for (const PreparedView& v : views) {
    result.views_used.push_back(v.index);
    relative.push_back(v.chain.T_cambody_boardbody);
  }
  const MotionSpread spread = MeasureMotionSpread(relative);
  result.rotation_spread_deg = spread.rotation_spread_deg;
  result.axis_spread_deg = spread.axis_spread_deg;
}

}  // namespace

void CameraMountOptions::check() const {
  if (min_views < 3) throw InputError("CameraMountOptions.min_views", Str("is ", min_views, "; need >= 3"));
  if (min_corners_per_view < 4)
    throw InputError("CameraMountOptions.min_corners_per_view", Str("is ", min_corners_per_view, "; need >= 4"));
  if (!(max_pnp_rms_px > 0)) throw InputError("CameraMountOptions.max_pnp_rms_px", "must be positive");
  if (!(huber_px > 0)) throw InputError("CameraMountOptions.huber_px", "must be positive");
  if (!(max_view_rms_px > 0)) throw InputError("CameraMountOptions.max_view_rms_px", "must be positive");
  if (max_iterations < 1) throw InputError("CameraMountOptions.max_iterations", "must be at least 1");
  if (!(min_rotation_spread_deg >= 0)) throw InputError("CameraMountOptions.min_rotation_spread_deg", "must be >= 0");
  if (!(min_axis_spread_deg >= 0)) throw InputError("CameraMountOptions.min_axis_spread_deg", "must be >= 0");
}

HandEyeMount InitialiseMountHandEye(std::span<const Rigid3d> T_camera_board, std::span<const Rigid3d> T_cambody_boardbody) {
  MOCAP_CHECK(T_camera_board.size() == T_cambody_boardbody.size() && T_camera_board.size() >= 3, "need >= 3 paired poses");
  std::vector<cv::Mat> R_world2cam, t_world2cam, R_base2gripper, t_base2gripper;
  for (size_t i = 0; i < T_camera_board.size(); ++i) {
    R_world2cam.push_back(cv::Mat(CvRotation(T_camera_board[i])));
    t_world2cam.push_back(cv::Mat(cv::Vec3d(T_camera_board[i].translation().data())));
    R_base2gripper.push_back(cv::Mat(CvRotation(T_cambody_boardbody[i])));
    t_base2gripper.push_back(cv::Mat(cv::Vec3d(T_cambody_boardbody[i].translation().data())));
  }
  cv::Mat R_base2world, t_base2world, R_gripper2cam, t_gripper2cam;
  cv::calibrateRobotWorldHandEye(R_world2cam, t_world2cam, R_base2gripper, t_base2gripper, R_base2world, t_base2world,
                                 R_gripper2cam, t_gripper2cam, cv::CALIB_ROBOT_WORLD_HAND_EYE_SHAH);
  HandEyeMount mount;
  mount.T_boardbody_board = RigidFromCvRt(R_base2world, t_base2world).inverse();  // base2world: T_board_boardbody
  mount.T_cambody_camera = RigidFromCvRt(R_gripper2cam, t_gripper2cam).inverse();  // gripper2cam: T_camera_cambody
  return mount;
}

MotionSpread MeasureMotionSpread(std::span<const Rigid3d> T_cambody_boardbody) {
  MotionSpread spread;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < T_cambody_boardbody.size(); ++i)
    for (size_t j = i + 1; j < T_cambody_boardbody.size(); ++j) {
      const Eigen::AngleAxisd delta((T_cambody_boardbody[i].inverse() * T_cambody_boardbody[j]).rotation());
      spread.rotation_spread_deg = std::max(spread.rotation_spread_deg, DegFromRad(delta.angle()));
      if (delta.angle() > RadFromDeg(2.0)) scatter += delta.angle() * delta.axis() * delta.axis().transpose();
    }
  const Eigen::Vector3d eigen = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();  // ascending
  if (eigen(2) > 0) spread.axis_spread_deg = DegFromRad(std::atan(std::sqrt(std::max(eigen(1), 0.0) / eigen(2))));
  return spread;
}

CameraMountResult CalibrateCameraMount(std::span<const MountView> views, const PinholeCamera& camera,
                                       const BoardSpec& spec, const CameraMountOptions& options) {
  options.check();
  spec.check();
  camera.check();
  if (spec.type != BoardType::kCharuco)
    throw InputError("camera-mount", "needs a ChArUco board: a checkerboard's corner order is ambiguous under a half "
                                     "turn, which flips the board's pose between views");
  CameraMountResult result;
  std::vector<PreparedView> prepared = PrepareViews(views, camera, spec, options, result.views_rejected);
  RequireViews(prepared.size(), views.size(), options, result.views_rejected);
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  const MountEstimate initial = HandEyeInitialisation(prepared);
  result.initial_rms_px = Residuals(prepared, points_board, camera, initial).total_rms_px;
  MountEstimate mount = RefineMount(Chain(prepared), points_board, camera, initial, options.huber_px, options.max_iterations);
  if (RejectBadViews(options, Residuals(prepared, points_board, camera, mount), prepared, result.views_rejected)) {
    RequireViews(prepared.size(), views.size(), options, result.views_rejected);
    mount = RefineMount(Chain(prepared), points_board, camera, mount, options.huber_px, options.max_iterations);
  }
  FillResult(prepared, points_board, camera, mount, result);
  AddMotionWarnings(options, result);
  return result;
}

}  // namespace mocap
