#include "cli/calibrate_views.h"

#include <cstdio>

#include "core/check.h"
#include "core/pose_stream.h"
#include "core/utc_time.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

pipeline::Rig RigOfSession(const SessionReader& session) {
  pipeline::Rig rig;
  rig.name = session.dir().filename().string();
  for (const CameraStreamInfo& c : session.manifest().cameras) {
    pipeline::RigCameraCalibration cal{c.name, c.color_camera, std::nullopt, std::nullopt, std::nullopt};
    if (!c.camera_body.empty()) cal.body = c.camera_body, cal.T_body_camera = c.T_body_camera;
    rig.cameras.push_back(cal);
  }
  return rig;
}

pipeline::RigCameraCalibration& Entry(pipeline::Rig& rig, const std::string& camera) {
  for (pipeline::RigCameraCalibration& c : rig.cameras)
    if (c.name == camera) return c;
  rig.cameras.push_back({camera, std::nullopt, std::nullopt, std::nullopt, std::nullopt});
  return rig.cameras.back();
}

std::optional<Rigid3d> BodyPose(const SessionReader& session, const std::string& body, int64_t stamp_ns) {
  const std::optional<std::string> tracker = session.TrackerOfBody(body);
  if (!tracker) return std::nullopt;
  const InterpolatedPose p = InterpolatePose(session.PoseSamples(*tracker, body), stamp_ns);
  return p.pose;
}

void PrintRejected(const std::vector<RejectedView>& rejected, const CalibrationViews& views) {
  for (size_t i = 0; i < rejected.size() && i < 8; ++i)
    std::printf("  rejected frame %lld: %s\n", static_cast<long long>(views.frame_index.at(static_cast<size_t>(rejected[i].index))),
                rejected[i].reason.c_str());
  if (rejected.size() > 8) std::printf("  ... and %zu more rejected\n", rejected.size() - 8);
}

}  // namespace

CalibrationInputs OpenCalibrationInputs(const fs::path& session_dir, const fs::path& rig_file, const std::string& camera) {
  CalibrationInputs in{SessionReader::Open(session_dir), {}, camera, "", {}, 0};
  const SessionManifest& m = in.session.manifest();
  if (m.cameras.empty()) throw InputError(session_dir.string(), "the session has no camera");
  if (in.camera_name.empty()) in.camera_name = m.cameras.front().name;
  const CameraStreamInfo* info = m.FindCamera(in.camera_name);
  if (!info) throw InputError(session_dir.string(), "no camera '" + in.camera_name + "' in the session");
  in.rig = rig_file.empty() ? RigOfSession(in.session) : pipeline::ReadRig(rig_file);
  const pipeline::RigCameraCalibration& cal = Entry(in.rig, in.camera_name);
  in.intrinsics = cal.intrinsics.value_or(info->color_camera);
  in.camera_body = cal.body.value_or(info->camera_body);
  in.latency_ns = in.rig.tracker_latency_ns;
  return in;
}

CalibrationViews DetectViews(const CalibrationInputs& in, const BoardSpec& spec, int every, bool with_poses,
                             const std::string& board_body) {
  const SessionReader& s = in.session;
  if (with_poses) {
    if (in.camera_body.empty()) throw InputError(s.dir().string(), "camera '" + in.camera_name + "' has no tracker body: give a rig with its body");
    for (const std::string& body : {in.camera_body, board_body})
      if (!s.TrackerOfBody(body))
        throw InputError(s.dir().string(), "no tracker of the session reports body '" + body +
                                               "': record the board with its tracker body in the volume");
  }
  CalibrationViews views;
  for (int64_t i = 0; i < s.frame_count(in.camera_name); i += every) {
    if (s.ColorPath(in.camera_name, i).empty()) continue;
    const cv::Mat image = s.LoadColor(in.camera_name, i);
    views.image_size = image.size();
    BoardDetection detection = DetectBoard(image, spec);
    if (!with_poses) {
      views.detections.push_back(std::move(detection)), views.frame_index.push_back(i);
      continue;
    }
    if (!detection.found()) continue;
    const int64_t t = s.frame(in.camera_name, i).record.stamp_ns + in.latency_ns;
    const std::optional<Rigid3d> cam = BodyPose(s, in.camera_body, t), board = BodyPose(s, board_body, t);
    if (!cam || !board) {
      ++views.frames_without_poses;
      continue;
    }
    views.mount_views.push_back({*cam, *board, detection});
    views.detections.push_back(std::move(detection)), views.frame_index.push_back(i);
  }
  if (views.frame_index.empty()) throw InputError(s.dir().string(), "no usable colour frame of camera '" + in.camera_name + "'");
  return views;
}

RelativePoseAt BodyPair(const CalibrationInputs& in, const std::string& board_body) {
  const SessionReader& s = in.session;
  std::vector<std::vector<PoseSample>> streams;
  for (const std::string& body : {in.camera_body, board_body}) {
    const std::optional<std::string> tracker = body.empty() ? std::nullopt : s.TrackerOfBody(body);
    if (!tracker)
      throw InputError(s.dir().string(), "no tracker of the session reports body '" + body +
                                             "': record the board with its tracker body in the volume");
    streams.push_back(s.PoseSamples(*tracker, body));
  }
  return RelativePoseFromStreams(std::move(streams[0]), std::move(streams[1]));
}

void RefuseExisting(const fs::path& file, bool force) {
  if (!file.empty() && !force && fs::exists(file)) throw InputError(file.string(), "exists; pass --force to replace it");
}

void SetIntrinsics(pipeline::Rig& rig, const std::string& camera, const PinholeCamera& intrinsics) {
  Entry(rig, camera).intrinsics = intrinsics;
}

std::string Provenance(const std::string& what) { return what + ", " + NowUtcIso8601(); }

const pipeline::LibraryObject& ObjectOnOneBody(const pipeline::ObjectLibrary& library, const std::string& name) {
  const pipeline::LibraryObject* found = library.Find(name);
  if (!found) throw InputError(library.file.string(), "no object '" + name + "'");
  if (found->mounts.size() != 1)
    throw InputError(library.file.string(), Str("object '", name, "' is carried by ", found->mounts.size(),
                                                " bodies; object-mount calibrates an object on one body"));
  return *found;
}

void WriteLibrary(pipeline::ObjectLibrary library, const std::string& file, const std::string& what) {
  if (fs::absolute(file).parent_path() != fs::absolute(library.file).parent_path())
    for (pipeline::LibraryObject& o : library.objects) o.mesh = o.mesh_path.string();
  pipeline::WriteObjectLibrary(library, file, Provenance(what));
  std::fprintf(stderr, "wrote %s\n", file.c_str());
}

nlohmann::json PoseJson(const Rigid3d& T) {
  const Eigen::Quaterniond& q = T.rotation();
  return {{"translation_m", {T.translation().x(), T.translation().y(), T.translation().z()}},
          {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
}

void SetColorDepth(pipeline::Rig& rig, const std::string& camera, const Rigid3d& T_color_depth) {
  Entry(rig, camera).T_color_depth = T_color_depth;
}

void SetMount(pipeline::Rig& rig, const std::string& camera, const std::string& body, const Rigid3d& T_body_camera) {
  pipeline::RigCameraCalibration& c = Entry(rig, camera);
  c.body = body, c.T_body_camera = T_body_camera;
}

void PrintIntrinsics(const std::string& camera, const IntrinsicsResult& r, const CalibrationViews& views) {
  const PinholeCamera& k = r.camera;
  std::printf("intrinsics of %s from %zu of %zu views: fx %.2f fy %.2f cx %.2f cy %.2f (std %.2f %.2f %.2f %.2f px)\n",
              camera.c_str(), r.views_used.size(), views.detections.size(), k.fx, k.fy, k.cx, k.cy, r.fx_std_px,
              r.fy_std_px, r.cx_std_px, r.cy_std_px);
  std::printf("RMS %.3f px, image coverage %.0f %%\n", r.rms_px, 100 * r.coverage);
  PrintRejected(r.views_rejected, views);
  for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
}

void PrintCameraMount(const CalibrationInputs& in, const CameraMountResult& r, const CalibrationViews& views) {
  auto print_pose = [](const char* name, const Rigid3d& T) {
    const Eigen::Vector3d t = T.translation() * 1000.0, rv = T.rvec();
    std::printf("%s: t [%.2f %.2f %.2f] mm, rvec [%.5f %.5f %.5f] rad\n", name, t.x(), t.y(), t.z(), rv.x(), rv.y(), rv.z());
  };
  std::printf("camera mount of %s on %s from %zu of %zu views (%d frames without both poses)\n", in.camera_name.c_str(),
              in.camera_body.c_str(), r.views_used.size(), views.mount_views.size(), views.frames_without_poses);
  print_pose("T_cambody_camera", r.T_cambody_camera);
  print_pose("T_boardbody_board", r.T_boardbody_board);
  std::printf("RMS %.3f px (%.3f mm on the board), from %.3f px after the hand-eye start; rotation spread %.1f deg, axis spread %.1f deg\n",
              r.rms_px, r.rms_mm, r.initial_rms_px, r.rotation_spread_deg, r.axis_spread_deg);
  PrintRejected(r.views_rejected, views);
  for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
}

}  // namespace mocap::cli
