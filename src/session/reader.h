#pragma once
// Reads a session directory (docs/session-format.md): the manifest, every stream's records (a torn last
// line is ignored and reported), images on demand, and tracker poses around camera frames.
#include <cstdint>
#include <filesystem>
#include <map>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/image.h"
#include "core/pose_stream.h"
#include "session/manifest.h"
#include "session/records.h"

namespace mocap {

struct SessionReaderOptions {
  /// A line whose checksum fails in the middle of a stream is an error (InputError naming file:line)
  /// unless this is set; then it is skipped and counted in StreamDiagnostics::corrupt_lines. A bad last
  /// line is skipped (the torn tail a crash leaves) in a session that was not closed; in one closed
  /// cleanly, a torn tail or fewer records than the manifest's `stream_records` is an error unless this is
  /// set (the file was cut or damaged after recording).
  bool skip_corrupt_records = false;
  void check() const {}
};

/// What reading one stream file found besides its records.
struct StreamDiagnostics {
  std::string file;           ///< relative to the session
  int64_t records = 0;
  bool torn_tail = false;     ///< the last line was incomplete or failed its checksum, and was ignored
  int64_t corrupt_lines = 0;  ///< lines skipped in the middle (only with skip_corrupt_records)
};

/// A camera record with what the reader found on disk.
struct CameraFrameEntry {
  CameraFrameRecord record;
  bool color_present = false;  ///< the record lists a colour file and it exists
  bool depth_present = false;
};

/// The tracker samples of one body bracketing a time (nullopt where the stream has none).
struct SamplesAround {
  std::optional<TrackerRecord> before;  ///< last sample with stamp_ns <= t
  std::optional<TrackerRecord> after;   ///< first sample with stamp_ns > t
};

class SessionReader {
 public:
  /// Throws InputError (naming file and position) when the folder or manifest is missing, the format
  /// version is unsupported, a field is missing, or a record is corrupt (see SessionReaderOptions).
  static SessionReader Open(const std::filesystem::path& dir, const SessionReaderOptions& options = {});

  const std::filesystem::path& dir() const { return dir_; }
  const SessionManifest& manifest() const { return manifest_; }
  /// False if the writer never closed (it crashed or is still recording).
  bool complete() const { return manifest_.complete; }
  const std::vector<StreamDiagnostics>& diagnostics() const { return diagnostics_; }

  // Cameras. `camera` is a name from the manifest (InputError otherwise); `index` is the record's
  // position in the stream, 0-based (MOCAP_CHECK on out of range).
  int64_t frame_count(const std::string& camera) const;
  const CameraFrameEntry& frame(const std::string& camera, int64_t index) const;
  std::span<const CameraFrameEntry> frames(const std::string& camera) const;
  std::filesystem::path ColorPath(const std::string& camera, int64_t index) const;  ///< "" if none
  std::filesystem::path DepthPath(const std::string& camera, int64_t index) const;  ///< "" if none
  /// Colour as CV_8UC3 BGR. Throws InputError naming the file when it is not listed, absent or corrupt.
  cv::Mat LoadColor(const std::string& camera, int64_t index) const;
  /// Depth in metres (0 = invalid), converted with the camera's depth_unit_m. Throws like LoadColor.
  DepthImage LoadDepth(const std::string& camera, int64_t index) const;

  // Trackers. Records in file order; samples per body sorted by stamp_ns (stable: equal stamps keep
  // file order).
  std::span<const TrackerRecord> tracker_records(const std::string& tracker) const;
  std::vector<TrackerRecord> BodyRecords(const std::string& tracker, const std::string& body) const;
  /// Built once at Open (cheap to call per frame); empty for a body without samples.
  const std::vector<PoseSample>& PoseSamples(const std::string& tracker, const std::string& body) const;
  /// The tracker (name) that reports `body`, or nullopt.
  std::optional<std::string> TrackerOfBody(const std::string& body) const;

  const std::vector<EventRecord>& events() const { return events_; }

  /// The samples of (tracker, body) bracketing the camera frame's stamp.
  SamplesAround SamplesAroundFrame(const std::string& camera, int64_t index, const std::string& tracker,
                                   const std::string& body) const;
  /// T_<tracker frame>_camera (colour optical frame) at the frame's stamp: the camera body's pose
  /// interpolated there, times the mount T_body_camera. Fails with kEmptyStream when the camera has no
  /// camera_body or no tracker reports it.
  InterpolatedPose CameraPoseAtFrame(const std::string& camera, int64_t index,
                                     const InterpolationOptions& options = {}) const;

 private:
  struct CameraStream {
    std::vector<CameraFrameEntry> entries;
  };
  struct TrackerStream {
    std::vector<TrackerRecord> records;
    std::map<std::string, std::vector<size_t>> by_body;  ///< indices sorted by stamp_ns
    std::map<std::string, std::vector<PoseSample>> poses_by_body;  ///< same order
  };
  const CameraStream& camera_stream(const std::string& camera) const;
  const TrackerStream& tracker_stream(const std::string& tracker) const;

  std::filesystem::path dir_;
  SessionManifest manifest_;
  std::map<std::string, CameraStream> cameras_;
  std::map<std::string, TrackerStream> trackers_;
  std::vector<EventRecord> events_;
  std::vector<StreamDiagnostics> diagnostics_;
};

}  // namespace mocap
