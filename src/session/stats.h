#pragma once
// What `mocaplabel info` reports about a session: frames per stream, duration and rates, gaps and
// dropouts per stream and per body, status counts, clock-fit residuals, missing files.
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/pose_stream.h"
#include "session/reader.h"

namespace mocap {

struct SessionStatsOptions {
  /// A span between consecutive samples (or frames) longer than this is reported as a gap (ns).
  int64_t gap_limit_ns = 500'000'000;
  /// How a camera body's pose is interpolated at frame times for frames_with_pose.
  InterpolationOptions interpolation;
  void check() const;
};

struct TimeSpan {
  int64_t start_ns = 0;
  int64_t end_ns = 0;
};

/// Timing of one stream of stamps (sorted).
struct StreamTiming {
  int64_t count = 0;
  int64_t start_ns = 0, end_ns = 0;
  double duration_s = 0.0;
  double rate_hz = 0.0;          ///< (count - 1) / duration, 0 below two stamps
  int64_t duplicates = 0;        ///< stamps equal to their predecessor
  std::vector<TimeSpan> gaps;    ///< consecutive stamps further apart than the gap limit
};

struct CameraStats {
  std::string name;
  int64_t records = 0;
  int64_t color_listed = 0, color_present = 0;
  int64_t depth_listed = 0, depth_present = 0;
  int64_t frames = 0;  ///< records with colour and depth both present
  /// Of `frames`, those where the camera body's pose interpolates; nullopt without a camera body.
  std::optional<int64_t> frames_with_pose;
  std::map<std::string, int64_t> pose_failures;  ///< interpolation failure name -> frames
  int64_t dropped_frames = 0;  ///< device frame numbers skipped between consecutive records
  bool frames_subset = false;  ///< the stream is a chosen subset (CameraStreamInfo): skips are not drops
  int64_t stamps_backwards = 0;  ///< records whose stamp is before their predecessor's (file order)
  StreamTiming timing;
};

struct BodyStats {
  std::string tracker, body;
  int64_t samples = 0;
  std::map<std::string, int64_t> status_counts;  ///< every PoseStatus name, zeros included
  std::vector<TimeSpan> dropouts;  ///< runs of samples without a usable pose (first..last stamp)
  int64_t dropped_frames = 0;      ///< tracker frame numbers skipped between consecutive samples
  double rms_error_max_m = 0.0;
  StreamTiming timing;
};

struct SessionStats {
  std::string dir;
  bool complete = false;
  int format_version = 0;
  std::string software_version, created_utc, source;
  int64_t gap_limit_ns = 0;                ///< the limit the gaps were found with
  int64_t frames = 0;                      ///< over all cameras
  std::optional<int64_t> frames_with_pose; ///< over cameras with a camera body; nullopt when none has one
  std::vector<std::string> missing_files;  ///< listed but absent images, relative to the session
  std::vector<CameraStats> cameras;
  std::vector<BodyStats> bodies;
  std::map<std::string, ClockFit> clock_fits;
  std::map<std::string, int64_t> event_counts;  ///< by kind
  std::vector<StreamDiagnostics> streams;
};

/// Precondition: none beyond an opened reader; options.check() is called.
SessionStats ComputeSessionStats(const SessionReader& reader, const SessionStatsOptions& options = {});

/// The `info --json` document (docs/session-format.md, "mocaplabel info"): frames, frames_with_pose
/// (null without a camera body), missing_files (count) and missing_file_list, cameras, tracker_bodies
/// keyed by body name ("tracker/body" when two trackers share a body name), clock_fits, events, streams.
nlohmann::json ToJson(const SessionStats& stats);

/// A few lines for people.
std::string FormatSessionStats(const SessionStats& stats);

}  // namespace mocap
