#pragma once
// What `mocaplabel calibrate` reads from a session: the camera, its rig entry, the board in every Nth
// colour frame, and for the mount the tracked camera and board bodies at each frame's time (with the
// rig's latency), and how it prints the results.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "calibrate/camera_mount.h"
#include "calibrate/intrinsics.h"
#include "calibrate/latency.h"
#include "pipeline/object_library.h"
#include "pipeline/rig.h"
#include "session/reader.h"

namespace mocap::cli {

/// What the board procedures (intrinsics, camera-mount, latency, depth-to-color) are given.
struct BoardSessionArgs {
  std::string session, board, camera, rig, out;
  int every = 1;
  bool force = false, json = false;
};

struct CalibrationInputs {
  SessionReader session;
  pipeline::Rig rig;  ///< --rig, or one made from the calibration recorded in the session
  std::string camera_name, camera_body;
  PinholeCamera intrinsics;
  int64_t latency_ns = 0;
};

/// InputError for a camera the session does not have, or a rig file that does not fit the session.
CalibrationInputs OpenCalibrationInputs(const std::filesystem::path& session, const std::filesystem::path& rig_file,
                                        const std::string& camera);

struct CalibrationViews {
  std::vector<BoardDetection> detections;  ///< one per frame looked at (intrinsics) or per mount view
  std::vector<MountView> mount_views;      ///< with_poses only; parallel to `detections`
  std::vector<int64_t> frame_index;        ///< parallel to `detections`: the camera frame
  cv::Size image_size;
  int frames_without_poses = 0;            ///< with_poses: frames where a body's pose was not known
};

/// Detects the board in every `every`-th colour frame. With poses, keeps only the frames where the
/// board was found and both bodies' poses are known at the frame's time + the rig's latency; InputError
/// naming the body when the session's trackers do not report it, or the camera has no body.
CalibrationViews DetectViews(const CalibrationInputs& in, const BoardSpec& spec, int every, bool with_poses,
                             const std::string& board_body);

/// inv(T_tracker_cambody(t)) * T_tracker_boardbody(t) from the session's streams (calibrate/latency.h);
/// InputError naming a body no tracker reports.
RelativePoseAt BodyPair(const CalibrationInputs& in, const std::string& board_body);

/// InputError "exists; pass --force to replace it" for an existing `file` unless `force` ("" passes):
/// a calibration never replaces a file silently.
void RefuseExisting(const std::filesystem::path& file, bool force);

void SetIntrinsics(pipeline::Rig& rig, const std::string& camera, const PinholeCamera& intrinsics);
/// A calibration file's first comment line: `what` (what was calibrated, from which session, with which
/// residuals) and when, "... by mocaplabel calibrate X, 2026-12-03T08:56:00Z".
std::string Provenance(const std::string& what);

/// The object `name` of `library`; InputError naming the library when it has no such object or the
/// object is carried by several bodies (object-mount calibrates an object on one body).
const pipeline::LibraryObject& ObjectOnOneBody(const pipeline::ObjectLibrary& library, const std::string& name);

/// Writes `library` to `file` with Provenance(`what`) first; mesh paths become absolute when the file goes
/// to another folder than the library was read from (they are written relative to the file's folder).
void WriteLibrary(pipeline::ObjectLibrary library, const std::string& file, const std::string& what);

/// A pose as the calibrate commands print it: {"translation_m": [x, y, z], "rotation_wxyz": [w, x, y, z]}.
nlohmann::json PoseJson(const Rigid3d& T);

void SetColorDepth(pipeline::Rig& rig, const std::string& camera, const Rigid3d& T_color_depth);
void SetMount(pipeline::Rig& rig, const std::string& camera, const std::string& body, const Rigid3d& T_body_camera);

void PrintIntrinsics(const std::string& camera, const IntrinsicsResult& r, const CalibrationViews& views);
void PrintCameraMount(const CalibrationInputs& in, const CameraMountResult& r, const CalibrationViews& views);

}  // namespace mocap::cli
