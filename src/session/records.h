#pragma once
// The records of a session's append-only streams (cameras/<name>/frames.jsonl,
// trackers/<name>/samples.jsonl, events.jsonl) and their JSON form. Each record is one line, checksummed
// by record_file.h, so a torn or corrupted line is detected rather than misread.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/pose_stream.h"
#include "core/rigid3.h"

namespace mocap {

/// One record of a camera stream: a colour image, a depth image, or both taken together (Kinect1
/// registered). A Kinect v2 exposes its colour some 15 ms after its depth: the capture pairs the two into
/// one record stamped at the colour, with the depth's own time in depth_stamp_ns; an importer may write
/// each as its own record with its own stamp.
struct CameraFrameRecord {
  int64_t frame = 0;         ///< device frame number (or the importer's running index)
  int64_t device_ticks = 0;  ///< device timestamp in device ticks (0 when the source has none)
  int64_t stamp_ns = 0;      ///< host monotonic time (ns) the frame is placed at
  std::string source_id;     ///< the source's id (TUM timestamp text, BOP im_id), "" for live capture
  /// Image files relative to the camera folder (e.g. "color/000012.png"); filled by the writer. Empty
  /// when the record carries no such image.
  std::string color_file, depth_file;
  /// Host time (ns) of the depth exposure where a record pairs depth taken apart from its colour (a
  /// Kinect v2: libfreenect2 gives each image its own device timestamp); 0 = taken at stamp_ns.
  int64_t depth_stamp_ns = 0;

  bool has_color() const { return !color_file.empty(); }
  /// When the depth image was taken: depth_stamp_ns, or stamp_ns when the record does not set it.
  int64_t depth_time_ns() const { return depth_stamp_ns != 0 ? depth_stamp_ns : stamp_ns; }
  bool has_depth() const { return !depth_file.empty(); }
};

/// One sample of one body from a tracker.
struct TrackerRecord {
  std::string body;
  PoseStatus status = PoseStatus::kValid;
  int64_t device_frame = 0;  ///< tracker frame number
  int64_t device_ticks = 0;  ///< tracker timestamp in its ticks (0 when the source has none)
  int64_t stamp_ns = 0;      ///< host monotonic time (ns)
  Rigid3d T_frame_body;      ///< body into the tracker's frame (TrackerStreamInfo::frame); see CarriesPose
  double rms_error_m = 0.0;  ///< tracker's fit error (NDI RMS), 0 when unknown
  uint32_t port_status = 0;  ///< raw device status bits, kept verbatim (0 when unknown)
};

/// Something that happened during recording: "gap", "reconnect", "drop", "error", "note", ...
struct EventRecord {
  int64_t stamp_ns = 0;
  std::string kind;
  std::string stream;  ///< stream the event concerns ("" for the session)
  std::string detail;
};

/// Whether a sample of this status stores its pose: all but missing and disabled (an out-of-volume NDI
/// sample still reports a transform; HasPose() decides whether it may be used).
bool CarriesPose(PoseStatus status);

/// "000123": the file stem of a camera record's images (the record's position in its stream), and of
/// every per-frame file that later stages write for it (label runs, the simulator's truth).
std::string FrameFileStem(int64_t index);

nlohmann::json ToJson(const CameraFrameRecord& record);
nlohmann::json ToJson(const TrackerRecord& record);
nlohmann::json ToJson(const EventRecord& record);
/// Each throws InputError naming `where` (file:line) and the field on a missing or mistyped field.
CameraFrameRecord CameraFrameRecordFromJson(const nlohmann::json& json, const std::string& where);
TrackerRecord TrackerRecordFromJson(const nlohmann::json& json, const std::string& where);
EventRecord EventRecordFromJson(const nlohmann::json& json, const std::string& where);

}  // namespace mocap
