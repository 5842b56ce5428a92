#pragma once
// OptiTrack Motive CSV exports (format versions 1.2x). Layout:
//   line 1: "Format Version,1.24,Take Name,...,Rotation Type,Quaternion,Length Units,Meters,..."
//   then header rows whose second cell is "Type" (Rigid Body / Rigid Body Marker / Marker), "Name",
//   "ID", a row naming the quantity (Rotation / Position / Mean Marker Error / Marker Quality), and the
//   axis row "Frame,Time (Seconds),X,Y,Z,W,...", then one row per frame. Blank cells mean the body or
//   marker was not seen in that frame.
// The quaternion component order is read from the axis row (Motive writes X,Y,Z,W), never assumed.
// Poses are T_world_body (Motive's global frame), converted to metres from "Length Units".
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/pose_stream.h"

namespace mocap::import {

struct MotiveRigidBody {
  std::string name;
  std::string id;
  /// One per frame; blank cells give status missing. stamp_ns = the row's "Time (Seconds)".
  std::vector<PoseSample> samples;
  /// Mean marker error per frame (metres) when the export has that column; NaN where blank.
  std::vector<double> mean_marker_error_m;
};

struct MotiveMarker {
  std::string name;  ///< "NEON_FRAME:Marker 001", "Unlabeled 1053"
  std::string type;  ///< "Marker" or "Rigid Body Marker"
  std::vector<std::optional<Eigen::Vector3d>> positions_m;  ///< per frame, empty where blank
};

struct MotiveOptions {
  bool keep_markers = true;  ///< parse marker columns too (they are not imported into sessions)
};

struct MotiveTake {
  std::filesystem::path file;
  std::map<std::string, std::string> info;  ///< the key/value pairs of line 1
  double length_unit_m = 1.0;               ///< metres per file unit
  std::vector<int64_t> frame_ids;           ///< "Frame" column
  std::vector<int64_t> stamps_ns;           ///< "Time (Seconds)" column, from the take start
  std::vector<MotiveRigidBody> rigid_bodies;
  std::vector<MotiveMarker> markers;
  std::vector<std::string> ignored_columns;  ///< "<type> <name> <quantity>" not understood, not read
};

/// Reads a Motive CSV export. Throws InputError (file:line) for a missing header row or column (e.g. a
/// rigid body without its Rotation W), a rotation type other than Quaternion, an unknown length unit,
/// a row with the wrong number of fields (truncated file), a non-numeric cell, a partly blank pose or a
/// quaternion whose norm is not 1.
MotiveTake ReadMotiveCsv(const std::filesystem::path& file, const MotiveOptions& options = {});

}  // namespace mocap::import
