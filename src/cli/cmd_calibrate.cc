// mocaplabel calibrate board|intrinsics|camera-mount|latency|depth-to-color|pivot|object-mount|check: the calibration procedures of src/calibrate on a
// recorded session (docs/calibration.md). The results go into a rig file through the pipeline's strict
// writer, with where they came from in its comment lines; an existing file is never replaced silently.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <nlohmann/json.hpp>

#include "calibrate/board_pose.h"
#include "calibrate/camera_mount.h"
#include "calibrate/latency.h"
#include "calibrate/intrinsics.h"
#include "cli/board_yaml.h"
#include "cli/calibrate_depth.h"
#include "cli/calibrate_pointer.h"
#include "cli/calibrate_labels.h"
#include "cli/calibrate_board_mesh.h"
#include "cli/calibrate_views.h"
#include "cli/commands.h"
#include "cli/parse_args.h"
#include "core/check.h"
#include "pipeline/rig.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using Common = BoardSessionArgs;

void AddCommon(CLI::App& app, Common& c) {
  app.add_option("session", c.session, "session folder")->required();
  app.add_option("--board", c.board, "board file (e.g. calib/boards/charuco_8x6_40mm.yaml)")->required();
  app.add_option("--camera", c.camera, "camera stream (default: the session's first)");
  app.add_option("--rig", c.rig, "rig file to start from (default: the calibration recorded in the session)");
  app.add_option("--every", c.every, "use every Nth frame")->check(CLI::Range(1, 1 << 20));
  app.add_option("--out", c.out, "write the rig with the result into this file");
  app.add_flag("--force", c.force, "replace --out when it exists");
  app.add_flag("--json", c.json, "print the result as one JSON object");
}

json CameraJson(const PinholeCamera& k) {
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy}, {"dist", k.dist}};
}

json RejectedJson(const std::vector<RejectedView>& rejected, const CalibrationViews& views) {
  json out = json::array();
  for (const RejectedView& r : rejected) out.push_back({{"frame", views.frame_index.at(static_cast<size_t>(r.index))}, {"reason", r.reason}});
  return out;
}

void WriteRigOut(const Common& c, const pipeline::Rig& rig, const std::string& what) {
  if (c.out.empty()) return;
  pipeline::WriteRig(rig, c.out, Provenance(what));
  std::fprintf(stderr, "wrote %s\n", c.out.c_str());
}

/// Before any work: an existing --out is refused unless --force.
void CheckOut(const Common& c) { RefuseExisting(c.out, c.force); }

int Intrinsics(const Common& c, const IntrinsicsOptions& options) {
  CheckOut(c);
  const BoardSpec spec = ReadBoardFile(c.board);
  CalibrationInputs in = OpenCalibrationInputs(c.session, c.rig, c.camera);
  const CalibrationViews views = DetectViews(in, spec, c.every, false, "");
  const IntrinsicsResult r = CalibrateIntrinsics(views.detections, views.image_size, spec, options);
  const json j = {{"camera", in.camera_name}, {"intrinsics", CameraJson(r.camera)}, {"rms_px", r.rms_px},
                  {"views", views.detections.size()}, {"views_used", r.views_used.size()},
                  {"views_rejected", RejectedJson(r.views_rejected, views)}, {"coverage", r.coverage},
                  {"std_px", {r.fx_std_px, r.fy_std_px, r.cx_std_px, r.cy_std_px}}, {"warnings", r.warnings}};
  if (c.json) std::printf("%s\n", j.dump().c_str());
  else PrintIntrinsics(in.camera_name, r, views);
  SetIntrinsics(in.rig, in.camera_name, r.camera);
  WriteRigOut(c, in.rig, Str("intrinsics of ", in.camera_name, " from ", c.session, " (", r.views_used.size(),
                             " views, RMS ", r.rms_px, " px, coverage ", r.coverage, ") by mocaplabel calibrate intrinsics"));
  return 0;
}

int CameraMount(const Common& c, const std::string& board_body, const CameraMountOptions& options) {
  CheckOut(c);
  const BoardSpec spec = ReadBoardFile(c.board);
  CalibrationInputs in = OpenCalibrationInputs(c.session, c.rig, c.camera);
  const CalibrationViews views = DetectViews(in, spec, c.every, true, board_body);
  const CameraMountResult r = CalibrateCameraMount(views.mount_views, in.intrinsics, spec, options);
  const json j = {{"camera", in.camera_name}, {"camera_body", in.camera_body}, {"board_body", board_body},
                  {"T_cambody_camera", PoseJson(r.T_cambody_camera)}, {"T_boardbody_board", PoseJson(r.T_boardbody_board)},
                  {"initial_rms_px", r.initial_rms_px}, {"rms_px", r.rms_px}, {"rms_mm", r.rms_mm},
                  {"views", views.mount_views.size()}, {"views_used", r.views_used.size()},
                  {"frames_without_poses", views.frames_without_poses},
                  {"rotation_spread_deg", r.rotation_spread_deg}, {"axis_spread_deg", r.axis_spread_deg},
                  {"warnings", r.warnings}};
  if (c.json) std::printf("%s\n", j.dump().c_str());
  else PrintCameraMount(in, r, views);
  SetMount(in.rig, in.camera_name, in.camera_body, r.T_cambody_camera);
  WriteRigOut(c, in.rig, Str("mount of ", in.camera_name, " on ", in.camera_body, " from ", c.session, " (",
                             r.views_used.size(), " views, RMS ", r.rms_px, " px / ", r.rms_mm,
                             " mm) by mocaplabel calibrate camera-mount"));
  return 0;
}

int Latency(const Common& c, const std::string& board_body, const LatencyOptions& options) {
  CheckOut(c);
  const BoardSpec spec = ReadBoardFile(c.board);
  CalibrationInputs in = OpenCalibrationInputs(c.session, c.rig, c.camera);
  const CalibrationViews views = DetectViews(in, spec, c.every, false, "");
  std::vector<StampedBoardPose> image_poses;
  for (size_t i = 0; i < views.detections.size(); ++i)
    if (views.detections[i].found())
      if (const std::optional<BoardPose> pose = EstimateBoardPose(views.detections[i], spec, in.intrinsics))
        image_poses.push_back({in.session.frame(in.camera_name, views.frame_index[i]).record.stamp_ns, pose->T_camera_board});
  const LatencyResult r = EstimateTrackerLatency(image_poses, BodyPair(in, board_body), options);
  const json j = {{"camera", in.camera_name}, {"tracker_latency_ms", r.tracker_latency_ns / 1e6}, {"rms_deg", r.rms_deg},
                  {"contrast", r.contrast}, {"turn_rms_deg", r.turn_rms_deg}, {"pairs_used", r.pairs_used},
                  {"frames_with_board", image_poses.size()}, {"warnings", r.warnings}};
  if (c.json) std::printf("%s\n", j.dump().c_str());
  else std::printf("tracker latency %.3f ms (%d frame pairs, %zu frames with the board; disagreement %.3f deg, contrast %.1f)\n",
                   r.tracker_latency_ns / 1e6, r.pairs_used, image_poses.size(), r.rms_deg, r.contrast);
  for (const std::string& w : r.warnings) if (!c.json) std::printf("warning: %s\n", w.c_str());
  in.rig.tracker_latency_ns = r.tracker_latency_ns;
  WriteRigOut(c, in.rig, Str("tracker latency from ", c.session, " (", r.pairs_used, " frame pairs, disagreement ", r.rms_deg,
                             " deg) by mocaplabel calibrate latency"));
  return 0;
}

/// The label run and the files it was made with (object-mount, check).
void AddLabelInputs(CLI::App& app, LabelsCalibrationArgs& a) {
  app.add_option("--labels", a.labels, "label run folder (default: SESSION/labels)");
  app.add_option("--objects", a.objects, "object library (default: the one the label run read)");
  app.add_option("--rig", a.rig, "rig file (default: the one the label run read, else the session's calibration)");
  app.add_flag("--force", a.force, "replace files written when they exist");
  app.add_flag("--json", a.json, "print the result as one JSON object");
}

}  // namespace

int RunCalibrate(int argc, char** argv) {
  CLI::App app{"Calibrate the rig from a recorded session: board, intrinsics, camera-mount, latency, depth-to-color, pivot, object-mount, check", "mocaplabel calibrate"};
  app.require_subcommand(1);
  std::string board_file, board_out;
  int pixels_per_square = 100;
  double thickness_mm = 3.0;
  bool board_force = false;
  CLI::App* board = app.add_subcommand("board", "draw a board for printing and as a textured mesh");
  board->add_option("board", board_file, "board file")->required();
  board->add_option("--out", board_out, "folder for board.png, board_mesh.obj/.mtl and board_texture.png")->required();
  board->add_option("--pixels-per-square", pixels_per_square, "drawing resolution")->check(CLI::Range(8, 2000));
  board->add_option("--thickness-mm", thickness_mm, "mesh thickness")->check(CLI::Range(0.1, 100.0));
  board->add_flag("--force", board_force, "replace existing files");

  Common intrinsics_args;
  IntrinsicsOptions intrinsics_options;
  CLI::App* intrinsics = app.add_subcommand("intrinsics", "camera intrinsics from views of the board");
  AddCommon(*intrinsics, intrinsics_args);
  intrinsics->add_option("--min-views", intrinsics_options.min_views, "usable views needed")->check(CLI::Range(3, 100000));

  Common mount_args;
  std::string board_body;
  CameraMountOptions mount_options;
  CLI::App* mount = app.add_subcommand("camera-mount", "T_cambody_camera (and the board on its body) from a tracked board");
  AddCommon(*mount, mount_args);
  mount->add_option("--board-body", board_body, "tracker body carrying the board")->required();
  mount->add_option("--min-views", mount_options.min_views, "usable views needed")->check(CLI::Range(3, 100000));
  Common depth_args;
  DepthToColorOptions depth_options;
  CLI::App* depth = app.add_subcommand("depth-to-color", "a Kinect v2's depth-to-colour extrinsic from the board's plane in both images");
  AddCommon(*depth, depth_args);
  depth->add_option("--min-views", depth_options.min_views, "views with a depth plane needed")->check(CLI::Range(3, 100000));
  Common latency_args;
  std::string latency_board_body;
  LatencyOptions latency_options;
  CLI::App* latency = app.add_subcommand("latency", "the tracker-to-camera latency from the board's motion in the images");
  AddCommon(*latency, latency_args);
  latency->add_option("--board-body", latency_board_body, "tracker body carrying the board")->required();

  LabelsCalibrationArgs object_args;
  ObjectMountOptions object_options;
  CLI::App* object = app.add_subcommand("object-mount", "T_body_mesh of an object from the recorded depth (SegICP)");
  object->add_option("session", object_args.session, "session folder")->required();
  object->add_option("--object", object_args.object, "the object (objects.yaml name)")->required();
  AddLabelInputs(*object, object_args);
  object->add_option("--validation", object_args.validation, "use this validation run's estimates (default: check here)");
  object->add_option("--frame-stride", object_args.frame_stride, "check every Nth frame")->check(CLI::Range(1, 1 << 20));
  object->add_option("--min-records", object_options.min_records, "reliable records needed")->check(CLI::Range(3, 1 << 20));
  object->add_option("--out", object_args.out, "write the object library with the new mount into this file");
  PointerArgs pointer_args;
  TouchOptions touch_options;
  object->add_option("--pointer", pointer_args.pointer, "pointer file (calibrate pivot): from landmarks touched with it, not the depth");
  object->add_option("--landmarks", pointer_args.landmarks, "landmarks file: the mesh points touched, in order (with --pointer)");
  object->add_option("--min-still-s", touch_options.min_still_s, "a touch: the tip at rest this long")->check(CLI::PositiveNumber);

  PivotOptions pivot_options;
  CLI::App* pivot = app.add_subcommand("pivot", "a tracked pointer's tip from pivoting it in a divot");
  pivot->add_option("session", pointer_args.session, "session folder")->required();
  pivot->add_option("--pointer-body", pointer_args.pointer_body, "the pointer's tracker body")->required();
  pivot->add_option("--from-s", pointer_args.from_s, "use the poses from this many seconds after the first")->check(CLI::NonNegativeNumber);
  pivot->add_option("--to-s", pointer_args.to_s, "... up to this many seconds after the first (default: the end)")->check(CLI::NonNegativeNumber);
  pivot->add_option("--out", pointer_args.out, "write the pointer file");
  pivot->add_flag("--force", pointer_args.force, "replace the pointer file when it exists");
  pivot->add_flag("--json", pointer_args.json, "print the result as one JSON object");

  LabelsCalibrationArgs check_args;
  CalibrationCheckOptions check_options;
  CLI::App* check = app.add_subcommand("check", "which calibration item looks wrong, from a validated session");
  check->add_option("session", check_args.session, "session folder")->required();
  check->add_option("--validation", check_args.validation, "validation run of the labels")->required();
  AddLabelInputs(*check, check_args);
  check->add_option("--min-mount-mm", check_options.min_mount_mm, "smallest mount error reported, mm")->check(CLI::PositiveNumber);
  check->add_option("--min-camera-mount-deg", check_options.min_camera_mount_deg, "smallest camera-mount rotation reported")->check(CLI::PositiveNumber);
  check->add_option("--min-object-mount-deg", check_options.min_object_mount_deg, "smallest object-mount rotation reported")->check(CLI::PositiveNumber);
  check->add_option("--min-latency-ms", check_options.min_latency_ms, "smallest latency error reported")->check(CLI::PositiveNumber);
  check->add_option("--write-rig", check_args.write_rig, "write the rig with the corrections into this file");
  check->add_option("--write-objects", check_args.write_objects, "write the object library with the corrections into this file");
  MOCAP_PARSE(app, argc, argv);

  if (*board) {
    for (const fs::path& f : WriteBoardFiles(ReadBoardFile(board_file), board_out, pixels_per_square, thickness_mm / 1000.0, board_force))
      std::printf("wrote %s\n", f.string().c_str());
    return 0;
  }
  if (*intrinsics) return Intrinsics(intrinsics_args, intrinsics_options);
  if (*latency) return Latency(latency_args, latency_board_body, latency_options);
  if (*pivot) return CalibratePivotOfSession(pointer_args, pivot_options);
  if (*depth)
    return CalibrateDepthToColorOfSession(depth_args, depth_options);
  if (*object && (!pointer_args.pointer.empty() || !pointer_args.landmarks.empty())) {
    if (pointer_args.pointer.empty() || pointer_args.landmarks.empty())
      throw InputError("calibrate object-mount", "--pointer and --landmarks go together");
    if (!object_args.validation.empty()) throw InputError("calibrate object-mount", "--validation is for the mount from depth, not with --pointer");
    pointer_args.session = object_args.session, pointer_args.object = object_args.object, pointer_args.objects = object_args.objects;
    pointer_args.out = object_args.out, pointer_args.force = object_args.force, pointer_args.json = object_args.json;
    return CalibrateObjectMountFromPointer(pointer_args, touch_options);
  }
  if (*object) return CalibrateObjectMountFromLabels(object_args, object_options);
  if (*check) return CheckCalibrationOfLabels(check_args, check_options);
  return CameraMount(mount_args, board_body, mount_options);
}

}  // namespace mocap::cli
