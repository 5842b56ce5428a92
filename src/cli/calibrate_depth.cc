#include "cli/calibrate_depth.h"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "calibrate/board_pose.h"
#include "cli/board_yaml.h"
#include "cli/calibrate_views.h"
#include "core/check.h"

namespace mocap::cli {
namespace {

using nlohmann::json;

/// The depth camera's points that lie on the board: within the board's outline less half a square (its
/// edges mix board and background depth) and within 3 cm of its plane, found through `T_color_depth`.
std::vector<Eigen::Vector3d> BoardPointsInDepth(const DepthImage& depth_m, const PinholeCamera& depth_camera, const Rigid3d& T_color_depth,
                                                const Rigid3d& T_color_board, const BoardSpec& spec) {
  const Rigid3d T_board_depth = T_color_board.inverse() * T_color_depth;
  const double margin = 0.5 * spec.square_m, width = spec.squares_x * spec.square_m, height = spec.squares_y * spec.square_m;
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector3d& p_depth : DepthToPoints(depth_m, depth_camera)) {
    const Eigen::Vector3d p_board = T_board_depth * p_depth;
    if (p_board.x() > margin && p_board.x() < width - margin && p_board.y() > margin && p_board.y() < height - margin &&
        std::abs(p_board.z()) < 0.03)
      points.push_back(p_depth);
  }
  return points;
}

}  // namespace

int CalibrateDepthToColorOfSession(const BoardSessionArgs& a, const DepthToColorOptions& options) {
  options.check();
  RefuseExisting(a.out, a.force);
  const BoardSpec spec = ReadBoardFile(a.board);
  CalibrationInputs in = OpenCalibrationInputs(a.session, a.rig, a.camera);
  const CameraStreamInfo& info = *in.session.manifest().FindCamera(in.camera_name);
  if (info.depth_registered_to_color)
    throw InputError(a.session, "camera '" + in.camera_name + "' records depth registered to its colour image: there is no depth-to-colour extrinsic to calibrate");
  const pipeline::RigCameraCalibration* cal = in.rig.Find(in.camera_name);
  const Rigid3d T_color_depth_before = cal && cal->T_color_depth ? *cal->T_color_depth : info.T_color_depth;
  const CalibrationViews views = DetectViews(in, spec, a.every, false, "");
  std::vector<PlanePair> pairs;
  int no_plane = 0;
  for (size_t i = 0; i < views.detections.size(); ++i) {
    if (!views.detections[i].found()) continue;
    const std::optional<BoardPose> pose = EstimateBoardPose(views.detections[i], spec, in.intrinsics);
    if (!pose) continue;
    const DepthImage depth_m = in.session.LoadDepth(in.camera_name, views.frame_index[i]);
    if (depth_m.width != info.depth_camera.width || depth_m.height != info.depth_camera.height)
      throw InputError(Str(a.session, " ", in.camera_name, " frame ", views.frame_index[i]),
                       Str("depth image is ", depth_m.width, "x", depth_m.height, ", the depth camera ", info.depth_camera.width, "x",
                           info.depth_camera.height));
    const std::optional<PlaneFit> fit = FitPlane(BoardPointsInDepth(depth_m, info.depth_camera, T_color_depth_before, pose->T_camera_board, spec));
    if (fit) pairs.push_back({fit->plane, BoardPlane(pose->T_camera_board)});
    else ++no_plane;
  }
  const DepthToColorResult r = EstimateDepthToColor(pairs, options);
  const Rigid3d change = T_color_depth_before.inverse() * r.T_color_depth;
  const double change_mm = 1e3 * change.translation().norm(), change_deg = DegFromRad(change.rvec().norm());
  if (a.json) {
    std::printf("%s\n", json{{"camera", in.camera_name}, {"T_color_depth", PoseJson(r.T_color_depth)}, {"T_color_depth_before", PoseJson(T_color_depth_before)},
                             {"change_mm", change_mm}, {"change_deg", change_deg}, {"views_used", pairs.size()}, {"views_without_plane", no_plane},
                             {"offset_rms_mm", r.offset_rms_mm}, {"offset_error_mm", r.offset_error_mm}, {"normal_error_deg", r.normal_error_deg}, {"normal_rms_deg", r.normal_rms_deg}, {"normal_spread_deg", r.normal_spread_deg},
                             {"warnings", r.warnings}}.dump().c_str());
  } else {
    const Eigen::Vector3d t_mm = 1e3 * r.T_color_depth.translation();
    std::printf("depth-to-colour of %s from %zu views (%d without a depth plane): t = [%.2f, %.2f, %.2f] mm; %.2f mm, %.3f deg from the device's\n",
                in.camera_name.c_str(), pairs.size(), no_plane, t_mm.x(), t_mm.y(), t_mm.z(), change_mm, change_deg);
    std::printf("plane offsets %.2f mm RMS, normals %.3f deg RMS, normals spread %.1f deg\n", r.offset_rms_mm, r.normal_rms_deg, r.normal_spread_deg);
    for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
  }
  if (a.out.empty()) return 0;
  SetColorDepth(in.rig, in.camera_name, r.T_color_depth);
  pipeline::WriteRig(in.rig, a.out, Provenance(Str("depth-to-colour extrinsic of ", in.camera_name, " from ", a.session, " (", pairs.size(), " views, plane offsets ",
                                        r.offset_rms_mm, " mm RMS) by mocaplabel calibrate depth-to-color")));
  std::fprintf(stderr, "wrote %s\n", a.out.c_str());
  return 0;
}

}  // namespace mocap::cli
