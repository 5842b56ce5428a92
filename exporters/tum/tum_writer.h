#pragma once
// The TUM RGB-D exporter (docs/export.md "TUM RGB-D"; formats.md §6 after TUM's "File Formats" page):
// one sequence folder per split and scene (session and camera), the files TUM's tools (associate.py,
// evaluate_ate.py, evaluate_rpe.py) and this project's importer (session/import/tum.h) read:
//
//   DIR/<split>/<scene_id:06d>/rgb.txt, depth.txt   '#' header lines, then "timestamp filename"
//   DIR/<split>/<scene_id:06d>/rgb/<stamp>.png|jpg   the recorded colour files, linked or copied
//   DIR/<split>/<scene_id:06d>/depth/<stamp>.png     uint16, 5000 per metre, 0 = no measurement,
//                                                    registered to the colour image
//   DIR/<split>/<scene_id:06d>/groundtruth.txt       "timestamp tx ty tz qx qy qz qw": T_tracker_camera
//   DIR/<split>/<scene_id:06d>/objects/<name>[_<instance>].txt   same format: T_tracker_mesh per label
//   DIR/<split>/<scene_id:06d>/camera.txt            colour intrinsics (TUM publishes them on a web page)
//
// Timestamps are the session's clock (stamp_ns: host monotonic time for captured sessions, the original
// Unix time for TUM imports) in seconds with 9 decimals, written exactly from the integer nanoseconds, so
// a re-import gives back the same stamps. A frame's pose lines carry the frame's own stamp: the tracker
// latency is already applied (ExportFrame::T_tracker_camera), so associate.py pairs images with poses at
// difference 0.
#include <filesystem>
#include <string>

#include "core/rigid3.h"
#include "exporters/dataset/dataset.h"

namespace mocap::exporters {

/// TUM depth PNG units per metre (formats.md §6; Open3D's CreateRGBDImageFromTUMFormat).
inline constexpr double kTumDepthPerMetre = 5000.0;

struct TumExportOptions {
  bool write_depth = true;    ///< depth.txt and depth/
  bool write_objects = true;  ///< objects/ trajectories
  /// Colour recorded as JPEG is linked as rgb/<stamp>.jpg and listed so (TUM's recordings are PNG, but
  /// the list names the file and image readers open either). true: decoded and written as PNG instead
  /// (lossless from the JPEG, not from the sensor; larger and slower).
  bool jpeg_to_png = false;
  /// A scene whose camera is tracked in no exported frame has no groundtruth. false: such a scene is an
  /// InputError. true: its groundtruth.txt holds only the header, and its object trajectories are
  /// written in the camera frame (T_camera_mesh) into objects_in_camera/ instead of objects/, so a
  /// camera-frame file is never mistaken for a world-frame one.
  bool camera_frame_when_untracked = false;
  int threads = 0;  ///< frames' images written in parallel; 0: one per core
  void check() const;
};

/// Writes the dataset as TUM RGB-D sequences into `dir` (normally an export's .partial folder). Throws
/// InputError naming the file on a failed write or unreadable input, and naming the scene for an
/// untracked camera (unless TumExportOptions::camera_frame_when_untracked).
WriteSummary WriteTum(const Dataset& dataset, const std::filesystem::path& dir, const TumExportOptions& options = {});

/// "seconds.nanoseconds" with 9 decimals, exact (no floating point): 1305031102175304000 ->
/// "1305031102.175304000". Exposed for tests.
std::string TumStampText(int64_t stamp_ns);

/// One line "timestamp tx ty tz qx qy qz qw" (metres with 9 decimals, quaternion scalar-last with 12,
/// qw >= 0), without the newline. Exposed for tests.
std::string TumPoseLine(int64_t stamp_ns, const Rigid3d& T_world_frame);

}  // namespace mocap::exporters
