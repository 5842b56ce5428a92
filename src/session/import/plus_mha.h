#pragma once
// PLUS sequence metafiles (PlusLib docs/file-formats/FileSequenceFile.md): a MetaIO header of
// "Key = value" lines, ending with "ElementDataFile = LOCAL", followed by the (here ignored) image
// payload. Per-frame fields are "Seq_Frame<idx>_<Name> = <value>":
//   <From>To<To>Transform        16 numbers, 4x4 row-major, translation in mm (NDI trackers)
//   <From>To<To>TransformStatus  OK | INVALID | MISSING | OUT_OF_VIEW | OUT_OF_VOLUME | REQ_TIMEOUT | DISABLED
//   Timestamp                    s, jitter-filtered (what PLUS interpolates on)
//   UnfilteredTimestamp          s, host receive time
//   FrameNumber                  device frame number
// Transforms map From into To (p_To = T_FromToTo * p_From), i.e. T_<To>_<From> in this project's naming.
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/pose_stream.h"

namespace mocap::import {

/// One transform channel, e.g. "ProbeToTracker".
struct PlusTransformTrack {
  std::string name;        ///< "ProbeToTracker"
  std::string from_frame;  ///< "Probe"
  std::string to_frame;    ///< "Tracker"
  /// One per sequence frame: T_to_from in metres; status from the <Name>TransformStatus field
  /// (absent field: valid). stamp_ns = the frame's Timestamp.
  std::vector<PoseSample> samples;
  std::vector<std::string> source_status;  ///< the status text as written ("OK", "INVALID"; "" if absent)
};

struct PlusFrame {
  int index = 0;                         ///< <idx> in Seq_Frame<idx>
  int64_t stamp_ns = 0;                  ///< Timestamp
  std::optional<int64_t> unfiltered_stamp_ns;  ///< UnfilteredTimestamp
  std::optional<int64_t> frame_number;   ///< FrameNumber
  std::string image_status;              ///< ImageStatus as written ("" if absent)
};

struct PlusSequence {
  std::filesystem::path file;
  std::map<std::string, std::string> header;  ///< MetaIO header fields (not per-frame)
  std::vector<PlusFrame> frames;
  std::vector<PlusTransformTrack> transforms;  ///< in order of first appearance
  /// Per-frame fields that are neither a transform, its status nor a known field (e.g. a custom
  /// "Stylus" matrix without the <From>To<To>Transform name): listed, not imported.
  std::vector<std::string> ignored_fields;
};

/// Maps a PLUS tool status to PoseStatus: OK → valid; OUT_OF_VOLUME → out_of_volume; DISABLED →
/// disabled; INVALID, MISSING, OUT_OF_VIEW, REQ_TIMEOUT, UNKNOWN → missing. Empty when unknown.
std::optional<PoseStatus> PoseStatusFromPlus(std::string_view status);

/// Reads a .mha/.igs.mha tracking sequence. Throws InputError (file:line) for a malformed line, a
/// transform that is not 16 numbers or not rigid, an unknown status, a frame without Timestamp, or
/// fewer frames than DimSize announces (a truncated file).
PlusSequence ReadPlusSequence(const std::filesystem::path& file);

}  // namespace mocap::import
