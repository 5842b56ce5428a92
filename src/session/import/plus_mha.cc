#include "session/import/plus_mha.h"

#include <algorithm>
#include <cctype>

#include "core/check.h"
#include "core/text.h"
#include "session/import/text_parse.h"

namespace mocap::import {
namespace {

constexpr std::string_view kFramePrefix = "Seq_Frame";
constexpr std::string_view kTransformSuffix = "Transform";
constexpr std::string_view kStatusSuffix = "TransformStatus";

struct Field {
  std::string value;
  int line = 0;
};

// Per-frame fields by name, with the line each came from (for error messages).
using FrameFields = std::map<std::string, Field>;

struct RawSequence {
  std::map<std::string, std::string> header;
  std::map<int, FrameFields> frames;
  std::vector<std::string> field_order;  // per-frame field names in order of first appearance
  size_t payload_offset = 0;             // byte offset just after the ElementDataFile line
};

bool EndsWith(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}

// "Seq_Frame0012_ProbeToTrackerTransform" -> (12, "ProbeToTrackerTransform"); empty when not per-frame.
std::optional<std::pair<int, std::string>> SplitFrameKey(std::string_view key, const std::string& where) {
  if (key.substr(0, kFramePrefix.size()) != kFramePrefix) return std::nullopt;
  const size_t underscore = key.find('_', kFramePrefix.size());
  if (underscore == std::string_view::npos || underscore + 1 >= key.size())
    throw InputError(where, Str("malformed per-frame key ", QuoteForMessage(key), " (expected Seq_Frame<idx>_<Name>)"));
  const int64_t index = ParseInt(key.substr(kFramePrefix.size(), underscore - kFramePrefix.size()), where);
  if (index < 0 || index > 100'000'000) throw InputError(where, Str("frame index ", index, " out of range"));
  return std::pair{static_cast<int>(index), std::string(key.substr(underscore + 1))};
}

RawSequence ReadRaw(const std::filesystem::path& file, const std::string& bytes) {
  RawSequence raw;
  size_t start = 0;
  int line_number = 0;
  while (true) {
    if (start >= bytes.size())
      throw InputError(file.string(), "header ends without 'ElementDataFile = LOCAL' (truncated or not a PLUS sequence)");
    size_t end = bytes.find('\n', start);
    if (end == std::string::npos) end = bytes.size();
    // Field names are the user's text: a header line that is not UTF-8 is read as Windows-1252.
    const std::string utf8_line = TextToUtf8(Trim(std::string_view(bytes).substr(start, end - start)));
    const std::string_view line = utf8_line;
    start = end + 1;
    const std::string where = Where(file, ++line_number);
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos) throw InputError(where, Str("expected 'Key = value', got ", QuoteForMessage(line, 60)));
    const std::string key(Trim(line.substr(0, eq)));
    const std::string value(Trim(line.substr(eq + 1)));
    if (line_number == 1 && key != "ObjectType")
      throw InputError(where, "not a MetaIO sequence file (first line must be 'ObjectType = Image')");
    if (auto frame_key = SplitFrameKey(key, where)) {
      auto& fields = raw.frames[frame_key->first];
      if (fields.contains(frame_key->second)) throw InputError(where, Str("field ", QuoteForMessage(key), " given twice"));
      if (std::find(raw.field_order.begin(), raw.field_order.end(), frame_key->second) == raw.field_order.end())
        raw.field_order.push_back(frame_key->second);
      fields[frame_key->second] = Field{value, line_number};
      continue;
    }
    raw.header[key] = value;
    if (key == "ElementDataFile") {
      raw.payload_offset = std::min(start, bytes.size());
      return raw;
    }
  }
}

// Number of bytes the image payload after the header must have; empty when it cannot be told.
std::optional<size_t> ExpectedPayloadBytes(const std::map<std::string, std::string>& header,
                                           const std::vector<int64_t>& dims, const std::string& where) {
  if (auto it = header.find("CompressedData"); it != header.end() && it->second == "True") {
    auto size = header.find("CompressedDataSize");
    if (size == header.end()) return std::nullopt;
    return static_cast<size_t>(ParseInt(size->second, where));
  }
  int64_t pixels = 1;
  for (int64_t d : dims) pixels *= d;
  if (pixels == 0) return 0;
  static const std::map<std::string, int> kElementBytes = {
      {"MET_UCHAR", 1}, {"MET_CHAR", 1}, {"MET_USHORT", 2}, {"MET_SHORT", 2}, {"MET_UINT", 4},
      {"MET_INT", 4},   {"MET_FLOAT", 4}, {"MET_DOUBLE", 8}};
  auto type = header.find("ElementType");
  if (type == header.end() || !kElementBytes.contains(type->second)) return std::nullopt;
  int64_t channels = 1;
  if (auto it = header.find("ElementNumberOfChannels"); it != header.end()) channels = ParseInt(it->second, where);
  return static_cast<size_t>(pixels * channels * kElementBytes.at(type->second));
}

std::vector<int64_t> DimSize(const std::map<std::string, std::string>& header, const std::string& where) {
  auto it = header.find("DimSize");
  if (it == header.end()) throw InputError(where, "header has no DimSize");
  std::vector<int64_t> dims;
  for (auto f : SplitWhitespace(it->second)) dims.push_back(ParseInt(f, where));
  if (dims.size() != 3) throw InputError(where, Str("DimSize has ", dims.size(), " values, expected 3 (W H frames)"));
  return dims;
}

Rigid3d ParseTransform(const Field& field, const std::filesystem::path& file) {
  const std::string where = Where(file, field.line);
  const auto parts = SplitWhitespace(field.value);
  if (parts.size() != 16) throw InputError(where, Str("transform has ", parts.size(), " numbers, expected 16 (4x4 row-major)"));
  Eigen::Matrix4d T;
  for (int k = 0; k < 16; ++k) T(k / 4, k % 4) = ParseDouble(parts[static_cast<size_t>(k)], where);
  if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9)
    throw InputError(where, "last row of the transform is not 0 0 0 1");
  const Eigen::Quaterniond q = RotationFromNearlyOrthonormal(T.topLeftCorner<3, 3>(), where);
  return Rigid3d(q, T.topRightCorner<3, 1>() * 1e-3);  // PLUS/NDI translations are in mm
}

// "<From>To<To>" splits at the first "To" after a non-empty name that starts a capitalised word, so
// "ToolToTracker" is Tool -> Tracker.
size_t SplitPosition(const std::string& name) {
  size_t to = name.find("To", 1);
  while (to != std::string::npos && (to + 2 >= name.size() || !std::isupper(static_cast<unsigned char>(name[to + 2]))))
    to = name.find("To", to + 1);
  return to;
}

bool IsTransformName(const std::string& name) { return SplitPosition(name) != std::string::npos; }

PlusTransformTrack MakeTrack(const std::string& field_name) {
  PlusTransformTrack track;
  track.name = field_name.substr(0, field_name.size() - kTransformSuffix.size());
  const size_t to = SplitPosition(track.name);
  track.from_frame = track.name.substr(0, to);
  track.to_frame = track.name.substr(to + 2);
  return track;
}

void AppendSample(PlusTransformTrack& track, const FrameFields& fields, int64_t stamp_ns,
                  const std::filesystem::path& file) {
  PoseSample sample;
  sample.stamp_ns = stamp_ns;
  std::string status_text;
  auto transform = fields.find(track.name + std::string(kTransformSuffix));
  auto status = fields.find(track.name + std::string(kStatusSuffix));
  if (status != fields.end()) {
    status_text = status->second.value;
    const auto parsed = PoseStatusFromPlus(status_text);
    if (!parsed) throw InputError(Where(file, status->second.line), Str("unknown transform status ", QuoteForMessage(status_text)));
    sample.status = *parsed;
  }
  if (transform == fields.end()) {
    sample.status = PoseStatus::kMissing;  // the tool has no entry in this frame
  } else if (HasPose(sample.status)) {
    sample.pose = ParseTransform(transform->second, file);  // an INVALID row's matrix is not read
  }
  track.samples.push_back(sample);
  track.source_status.push_back(status_text);
}

}  // namespace

std::optional<PoseStatus> PoseStatusFromPlus(std::string_view status) {
  if (status == "OK") return PoseStatus::kValid;
  if (status == "OUT_OF_VOLUME") return PoseStatus::kOutOfVolume;
  if (status == "DISABLED") return PoseStatus::kDisabled;
  for (std::string_view missing : {"INVALID", "MISSING", "OUT_OF_VIEW", "REQ_TIMEOUT", "UNKNOWN"})
    if (status == missing) return PoseStatus::kMissing;
  return std::nullopt;
}

PlusSequence ReadPlusSequence(const std::filesystem::path& file) {
  const std::string bytes = ReadTextFile(file);
  RawSequence raw = ReadRaw(file, bytes);
  PlusSequence seq;
  seq.file = file;
  seq.header = raw.header;
  const std::vector<int64_t> dims = DimSize(raw.header, file.string());
  if (static_cast<int64_t>(raw.frames.size()) != dims[2])
    throw InputError(file.string(), Str("DimSize announces ", dims[2], " frames but the header holds ", raw.frames.size(),
                                        " (truncated file?)"));
  if (auto expected = ExpectedPayloadBytes(raw.header, dims, file.string());
      expected && bytes.size() - raw.payload_offset < *expected)
    throw InputError(Str(file.string(), ": byte ", bytes.size()),
                     Str("image data truncated: ", *expected, " bytes announced after the header, ",
                         bytes.size() - raw.payload_offset, " present"));
  for (const auto& name : raw.field_order) {
    if (EndsWith(name, kTransformSuffix) && IsTransformName(name.substr(0, name.size() - kTransformSuffix.size())))
      seq.transforms.push_back(MakeTrack(name));
    else if (!EndsWith(name, kStatusSuffix) && name != "Timestamp" && name != "UnfilteredTimestamp" &&
             name != "FrameNumber" && name != "ImageStatus")
      seq.ignored_fields.push_back(name);
  }
  int expected_index = 0;
  for (const auto& [index, fields] : raw.frames) {
    if (index != expected_index++)
      throw InputError(file.string(), Str("frame indices are not consecutive: Seq_Frame", index, " follows ", index - 1));
    PlusFrame frame;
    frame.index = index;
    auto stamp = fields.find("Timestamp");
    if (stamp == fields.end()) throw InputError(file.string(), Str("Seq_Frame", index, " has no Timestamp"));
    frame.stamp_ns = NanosecondsFromSeconds(stamp->second.value, Where(file, stamp->second.line));
    if (auto it = fields.find("UnfilteredTimestamp"); it != fields.end())
      frame.unfiltered_stamp_ns = NanosecondsFromSeconds(it->second.value, Where(file, it->second.line));
    if (auto it = fields.find("FrameNumber"); it != fields.end())
      frame.frame_number = ParseInt(it->second.value, Where(file, it->second.line));
    if (auto it = fields.find("ImageStatus"); it != fields.end()) frame.image_status = it->second.value;
    if (!seq.frames.empty() && frame.stamp_ns < seq.frames.back().stamp_ns)
      throw InputError(Where(file, stamp->second.line), "Timestamp goes backwards");
    for (auto& track : seq.transforms) AppendSample(track, fields, frame.stamp_ns, file);
    seq.frames.push_back(frame);
  }
  return seq;
}

}  // namespace mocap::import
