#pragma once
// What every importer shares: its summary (counts and notes for the CLI and the tests), and the
// bookkeeping of a pose stream's gaps and duplicated stamps, which importers also log as session events
// so that a session says what its source lacked.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "core/pose_stream.h"
#include "session/manifest.h"
#include "session/records.h"

namespace mocap {
class SessionWriter;
}

namespace mocap::import {

struct TimeGap {
  int64_t start_ns = 0;  ///< stamp of the sample before the gap
  int64_t end_ns = 0;    ///< stamp of the sample after it
};

/// Per tracker body: what its source stream looked like.
struct BodySummary {
  int64_t samples = 0;
  std::map<std::string, int64_t> status_counts;  ///< ToString(PoseStatus) -> samples
  int64_t duplicate_stamps = 0;                  ///< samples with the same stamp as the previous one
  std::vector<TimeGap> gaps;                     ///< spans between consecutive samples over the limit
};

struct ImportSummary {
  std::filesystem::path session;
  int64_t camera_records = 0;              ///< records written to camera streams
  int64_t frames_with_color_and_depth = 0; ///< records whose colour and depth files are both present
  int64_t frames_color_only = 0;           ///< records with a present colour file and no depth
  int64_t missing_files = 0;               ///< listed image files that do not exist (recorded as missing)
  int64_t tracker_samples = 0;
  std::map<std::string, BodySummary> bodies;  ///< "tracker/body" -> summary
  std::vector<std::string> notes;             ///< decisions taken for this source (shown to the user)
};

/// Writes the samples of one body to `tracker`, fills `summary.bodies["tracker/body"]`, and logs one
/// "gap" event per span over `gap_limit_ns` and one "duplicate_stamp" event per repeated stamp.
/// `records` must be sorted by stamp_ns.
void WriteBodySamples(SessionWriter& writer, const std::string& tracker, std::span<const TrackerRecord> records,
                      int64_t gap_limit_ns, ImportSummary& summary);

/// The range a number option accepts, shared by an options struct's check() and the CLI flag that sets
/// it, so both refuse the same values (1e300 Hz would otherwise overflow a stamp in nanoseconds).
struct NumberRange {
  double min = 0, max = 0;
  const char* unit = "";
};
inline constexpr NumberRange kTimeSpanRangeS{1e-6, 1e6, "s"};  ///< --gap-limit, --max-difference
inline constexpr NumberRange kBopFrameRateRangeHz{0.01, 1e5, "Hz"};
inline constexpr NumberRange kDepthUnitsPerMetreRange{1, 1e6, "units per metre"};
inline constexpr NumberRange kFocalLengthRangePx{1, 1e5, "px"};

/// `value` when it is finite and within `range`; else InputError(name, "must be between ...").
double CheckInRange(double value, const NumberRange& range, const std::string& name);

/// Rejects a session folder that exists and is not empty (InputError naming it), as the writer would,
/// before any source is read, so a bad --out fails fast.
void CheckOutputFolder(const std::filesystem::path& out);

/// Where an import writes before it is published: `<out>.partial`, a sibling of `out`.
std::filesystem::path PartialFolder(const std::filesystem::path& out);

/// Fills `<out>.partial` with a SessionWriter made from `manifest` and `write` (which gets the writer and
/// the partial folder, for files beside the streams), closes it and renames it to `out`, so `out` only
/// ever appears whole. On any error the partial folder is removed before the exception leaves, so a bad
/// source or a full disk leaves nothing behind and a rerun is not refused. A `<out>.partial` left by an
/// import that was killed (it holds a manifest.json, or nothing) is replaced; any other is refused.
/// Errors that would not name a file (a manifest check, text JSON cannot store) are reported against
/// `source`.
void PublishSession(const std::filesystem::path& out, const std::filesystem::path& source, SessionManifest manifest,
                    const std::function<void(SessionWriter&, const std::filesystem::path& dir)>& write);

}  // namespace mocap::import
