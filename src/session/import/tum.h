#pragma once
// TUM RGB-D benchmark sequences (Sturm et al., IROS 2012; format: the TUM "File Formats" page).
//   rgb.txt, depth.txt: "timestamp filename" per line, seconds since the Unix epoch.
//   groundtruth.txt:    "timestamp tx ty tz qx qy qz qw" — the pose of the colour camera's optical centre
//                       in the motion-capture world (metres, quaternion scalar-last).
//   depth PNG:          uint16, 5000 units per metre, 0 = no measurement; registered to the colour camera.
// Lines starting with '#' are comments. Some published index files lost the '#' of their header line
// ("timestamp filename"); such non-numeric lines are accepted before the first data line only.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/pose_stream.h"

namespace mocap::import {

/// TUM depth PNG units per metre.
inline constexpr double kTumDepthUnitsPerMetre = 5000.0;

/// One line of rgb.txt or depth.txt.
struct TumImageEntry {
  int64_t stamp_ns = 0;
  std::string stamp_text;      ///< the timestamp exactly as written (kept as the frame's source id)
  std::string relative_path;   ///< as written, relative to the sequence folder
  int line = 0;                ///< 1-based line in the list file
  bool exists = false;         ///< whether the image file is present
};

struct TumImageList {
  std::filesystem::path file;
  std::vector<TumImageEntry> entries;   ///< in file order (TUM writes them sorted by time)
  std::string bag_name;                 ///< from the "# file: '...bag'" comment, empty when absent
  std::vector<int> header_lines_without_hash;  ///< lines accepted as a header that lost its '#'
  int missing_files() const;
};

/// Reads rgb.txt / depth.txt; image paths are checked against `sequence_dir`. Throws InputError
/// (file:line) for a line that is not "timestamp filename" after the first data line.
TumImageList ReadTumImageList(const std::filesystem::path& list_file, const std::filesystem::path& sequence_dir);

struct TumGroundTruth {
  std::filesystem::path file;
  std::vector<PoseSample> samples;        ///< T_world_camera, sorted by stamp; all valid
  std::vector<std::string> stamp_texts;   ///< as written, parallel to samples
  int duplicate_stamps = 0;               ///< samples whose stamp equals the previous one (both kept)
};

/// Reads groundtruth.txt. Throws InputError (file:line) for a wrong field count, a non-numeric field,
/// a non-unit quaternion or a time that goes backwards.
TumGroundTruth ReadTumGroundTruth(const std::filesystem::path& file);

struct TumAssociationOptions {
  int64_t max_difference_ns = 20'000'000;  ///< associate.py --max_difference 0.02
  int64_t offset_ns = 0;                   ///< added to the second list's stamps (associate.py --offset)
  void check() const;
};

struct TumAssociation {
  size_t first = 0;   ///< index into the first list (rgb)
  size_t second = 0;  ///< index into the second list (depth)
  int64_t difference_ns = 0;  ///< |first - (second + offset)|
};

/// TUM's associate.py: all pairs closer than max_difference, accepted greedily nearest first, each
/// stamp used at most once; returned sorted by the first list's stamp. Stamps must be sorted.
std::vector<TumAssociation> AssociateTum(const std::vector<int64_t>& first_ns, const std::vector<int64_t>& second_ns,
                                         const TumAssociationOptions& options = {});

/// Colour camera models published by TUM ("File Formats", camera calibration), 640x480.
enum class TumCameraPreset { kFreiburg1, kFreiburg2, kFreiburg3, kRosDefault };
PinholeCamera TumCamera(TumCameraPreset preset);
/// The preset named by the bag file (rgbd_dataset_freiburgN_...), or empty when the name says nothing.
std::optional<TumCameraPreset> TumPresetFromBagName(const std::string& bag_name);
/// "fr1", "fr2", "fr3", "ros" → preset; throws InputError otherwise.
TumCameraPreset TumPresetFromName(const std::string& name);

struct TumSequence {
  std::filesystem::path dir;
  TumImageList rgb;
  TumImageList depth;
  TumGroundTruth groundtruth;
  std::vector<TumAssociation> rgb_depth;  ///< rgb index, depth index
};

/// Reads rgb.txt, depth.txt and groundtruth.txt of a sequence folder and associates rgb to depth.
TumSequence ReadTumSequence(const std::filesystem::path& dir, const TumAssociationOptions& options = {});

}  // namespace mocap::import
