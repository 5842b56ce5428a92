#pragma once
// The session manifest (manifest.json): what was recorded, by which devices, on which clock.
// Layout and every field are documented in docs/session-format.md.
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/clock.h"
#include "core/rigid3.h"

namespace mocap {

/// Version of the on-disk layout this code writes; the reader accepts exactly the versions it knows.
inline constexpr int kSessionFormatVersion = 1;

/// One camera (an RGB-D sensor, or an RGB-only source such as a BOP scene without depth).
struct CameraStreamInfo {
  std::string name;            ///< stream name, also its folder under cameras/ ("kinect1", "rgb")
  std::string model, serial;   ///< model: "kinect1", "kinect2", "tum", "bop", "sim", ...
  /// A time-of-flight depth camera (the Kinect v2; the Kinect v1 projects structured light).
  bool time_of_flight() const { return model == "kinect2"; }
  PinholeCamera color_camera;  ///< intrinsics of the colour stream
  PinholeCamera depth_camera;  ///< intrinsics of depth (equal to color_camera when registered)
  bool depth_registered_to_color = true;
  Rigid3d T_color_depth;       ///< depth optical frame into the colour optical frame
  double depth_unit_m = 0.001; ///< metres per unit of a 16-bit depth PNG (Kinect mm 0.001, TUM 1/5000)
  /// The smallest change of depth the camera reports at range z_m, metres: one disparity step of the
  /// Kinect v1, m/(f b) z^2 with m/(f b) = 2.85e-3 per metre (kinect.md section 8, after Khoshelham and
  /// Elberink 2012), else one unit of the depth images.
  double depth_step_m(double z_m) const { return model == "kinect1" ? 2.85e-3 * z_m * z_m : depth_unit_m; }
  std::string camera_body;     ///< tracker body carrying this camera ("" if none)
  Rigid3d T_body_camera;       ///< mount: colour optical frame into the body frame
  /// The stream holds a chosen subset of the recording's frames (a BOP test subset ships every few
  /// images): gaps in frame numbers are by design, not drops, and there is no frame rate to speak of.
  bool frames_subset = false;
};

/// One tracker (an NDI system, a Motive take, a ground-truth trajectory, known BOP object poses).
struct TrackerStreamInfo {
  std::string name, model, serial;
  /// Frame the poses are given in: "tracker" (the mocap world) or "camera:<camera name>" for known
  /// per-frame object poses in that camera's colour optical frame.
  std::string frame = "tracker";
  std::vector<std::string> bodies;  ///< bodies this tracker reports (samples may only name these)
};

struct SessionManifest {
  int format_version = kSessionFormatVersion;
  std::string software_version;  ///< mocaplabel version that wrote the session
  std::string created_utc;       ///< ISO 8601, e.g. "2026-11-24T10:00:00Z"; filled by the writer if empty
  std::string source;            ///< "capture", "import tum DIR", "sim", ...
  std::vector<CameraStreamInfo> cameras;
  std::vector<TrackerStreamInfo> trackers;
  std::map<std::string, ClockFit> clock_fits;  ///< per device (keyed by stream name or serial)
  nlohmann::json extra = nlohmann::json::object();  ///< importer/rig specifics, kept verbatim
  bool complete = false;  ///< set by SessionWriter::Close(); false after a crash
  /// Set by SessionWriter::Close(): the records in each stream file (by path relative to the session), so
  /// that a reader tells a file cut or damaged after recording from a complete one. Empty in sessions
  /// written before this field existed.
  std::map<std::string, int64_t> stream_records;

  /// Throws InputError (naming the field) on empty or duplicate stream names, names that are not
  /// plain file names, non-positive depth_unit_m, invalid intrinsics, unknown tracker frames.
  void check() const;
  const CameraStreamInfo* FindCamera(const std::string& name) const;
  const TrackerStreamInfo* FindTracker(const std::string& name) const;
};

nlohmann::json ToJson(const SessionManifest& manifest);
/// Throws InputError naming `where` (the file) and the JSON field on a missing or mistyped field or an
/// unsupported format_version.
SessionManifest ManifestFromJson(const nlohmann::json& json, const std::string& where);

nlohmann::json ToJson(const Rigid3d& pose);  ///< {"t_m": [x, y, z], "q_wxyz": [w, x, y, z]}
Rigid3d RigidFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json ToJson(const PinholeCamera& camera);
PinholeCamera PinholeFromJson(const nlohmann::json& json, const std::string& where);
nlohmann::json ToJson(const ClockFit& fit);
ClockFit ClockFitFromJson(const nlohmann::json& json, const std::string& where);

/// The session's stream files, relative to its folder (docs/session-format.md "Layout").
std::filesystem::path CameraStreamFile(const std::string& camera);    ///< cameras/<camera>/frames.jsonl
std::filesystem::path TrackerStreamFile(const std::string& tracker);  ///< trackers/<tracker>/samples.jsonl
/// manifest.json and every stream file of the manifest's cameras and trackers: what a session's content
/// is, besides the images its camera records name (provenance hashes these).
std::vector<std::filesystem::path> SessionStreamFiles(const SessionManifest& manifest);

/// Writes manifest.json atomically (temporary file, fsync, rename, fsync of the folder).
void SaveManifest(const std::filesystem::path& session_dir, const SessionManifest& manifest);
/// Reads and checks <session_dir>/manifest.json.
SessionManifest LoadManifest(const std::filesystem::path& session_dir);

}  // namespace mocap
