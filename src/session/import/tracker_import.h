#pragma once
// `mocaplabel import plus` and `mocaplabel import motive`: tracker logs into sessions with one tracker
// stream and no camera.
//
// PLUS sequence metafile → tracker "plus": one body per <From>To<To>Transform channel, named <From>
// when every channel maps into the same frame (e.g. "Probe", "Reference" for ...ToTracker), else the
// full channel name. stamp_ns = Timestamp (the filtered time PLUS interpolates on), device_frame =
// FrameNumber (the Seq_Frame index when absent). Every non-OK status is imported with its PoseStatus
// (INVALID → missing) and also logged as a "source_status" event keeping the PLUS word.
//
// Motive CSV → tracker "motive": one body per rigid body (markers are not imported), stamp_ns = the
// "Time (Seconds)" column (from the take start), device_frame = the "Frame" column, rms_error_m = the
// mean marker error when exported. Blank cells → missing samples.
#include <filesystem>
#include <string>

#include "core/progress.h"
#include "session/import/import_common.h"

namespace mocap::import {

struct TrackerImportOptions {
  int64_t gap_limit_ns = 500'000'000;  ///< spans longer than this are logged as gaps
  std::string software_version;
  ProgressSink* progress = nullptr;  ///< frames (bodies) written / total; not owned, may be null
  void check() const;
};

/// Throws InputError for a bad source (file:line) or an `out` that exists and is not empty.
ImportSummary ImportPlus(const std::filesystem::path& mha_file, const std::filesystem::path& out,
                         const TrackerImportOptions& options = {});
ImportSummary ImportMotive(const std::filesystem::path& csv_file, const std::filesystem::path& out,
                           const TrackerImportOptions& options = {});

}  // namespace mocap::import
