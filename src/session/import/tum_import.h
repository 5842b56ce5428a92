#pragma once
// `mocaplabel import tum`: a TUM RGB-D sequence (or a bare ground-truth trajectory) into a session.
//
// Sequence folder → one camera "rgbd" and one tracker "groundtruth" with one body "camera":
//  - each rgb.txt entry becomes a camera record at its stamp, with the depth image associate.py pairs
//    with it (nearest first, within 20 ms); depth entries left unpaired become depth-only records;
//  - image files are hard-linked or copied, never re-encoded (depth stays 16-bit, depth_unit_m = 1/5000);
//  - listed images that are absent are recorded as listed-but-missing (counted, not fatal);
//  - source_id = the rgb.txt timestamp text (depth-only records: the depth.txt timestamp text);
//  - the ground truth is the pose of the colour camera's optical centre, so camera_body = "camera" and
//    T_body_camera = identity.
// A trajectory file (groundtruth.txt format) → only the tracker "groundtruth".
// Stamps are the source's Unix times in ns.
#include <filesystem>
#include <optional>
#include <string>

#include "core/camera.h"
#include "core/progress.h"
#include "session/import/import_common.h"
#include "session/import/tum.h"

namespace mocap::import {

struct TumImportOptions {
  /// Colour intrinsics. Empty: the preset named by rgb.txt's bag file (freiburg1/2/3), else ROS default.
  std::optional<PinholeCamera> camera;
  std::optional<TumCameraPreset> preset;  ///< used when `camera` is empty
  TumAssociationOptions association;
  int64_t gap_limit_ns = 500'000'000;     ///< ground-truth spans longer than this are logged as gaps
  /// Depth PNG values per metre (TUM: 5000); within kDepthUnitsPerMetreRange.
  double depth_units_per_metre = kTumDepthUnitsPerMetre;
  std::string software_version;
  ProgressSink* progress = nullptr;  ///< frames (bodies) written / total; not owned, may be null
  void check() const;
};

/// Imports `source` (a sequence folder or a trajectory file) into the new session folder `out`.
/// Throws InputError for a bad source (file:line) or an `out` that exists and is not empty.
ImportSummary ImportTum(const std::filesystem::path& source, const std::filesystem::path& out,
                        const TumImportOptions& options = {});

}  // namespace mocap::import
