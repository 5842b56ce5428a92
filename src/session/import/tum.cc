#include "session/import/tum.h"

#include <algorithm>
#include <tuple>

#include "core/check.h"
#include "core/text.h"
#include "session/import/text_parse.h"

namespace mocap::import {
namespace {

bool IsComment(std::string_view line) {
  line = Trim(line);
  return line.empty() || line.front() == '#';
}

bool StartsWithDigit(std::string_view field) {
  return !field.empty() && ((field[0] >= '0' && field[0] <= '9') || field[0] == '.' || field[0] == '-');
}

// "# file: 'rgbd_dataset_freiburg1_desk.bag'" -> "rgbd_dataset_freiburg1_desk.bag"
std::string BagNameFromComment(std::string_view line) {
  const size_t key = line.find("file:");
  if (key == std::string_view::npos) return {};
  std::string_view rest = Trim(line.substr(key + 5));
  if (rest.size() >= 2 && (rest.front() == '\'' || rest.front() == '"')) rest = rest.substr(1, rest.size() - 2);
  return std::string(rest);
}

}  // namespace

int TumImageList::missing_files() const {
  return static_cast<int>(std::count_if(entries.begin(), entries.end(), [](const auto& e) { return !e.exists; }));
}

TumImageList ReadTumImageList(const std::filesystem::path& list_file, const std::filesystem::path& sequence_dir) {
  const std::string text = ReadTextFile(list_file);
  TumImageList list;
  list.file = list_file;
  const auto lines = SplitLines(text);
  for (size_t i = 0; i < lines.size(); ++i) {
    const int line_number = static_cast<int>(i + 1);
    if (IsComment(lines[i])) {
      // A comment is the user's text: one that is not UTF-8 is read as Windows-1252.
      if (list.bag_name.empty()) list.bag_name = TextToUtf8(BagNameFromComment(lines[i]));
      continue;
    }
    const auto fields = SplitWhitespace(lines[i]);
    if (!StartsWithDigit(fields[0]) && list.entries.empty()) {
      list.header_lines_without_hash.push_back(line_number);  // e.g. "timestamp filename" without '#'
      continue;
    }
    const std::string where = Where(list_file, line_number);
    if (fields.size() != 2)
      throw InputError(where, Str("expected 'timestamp filename', got ", fields.size(), " fields"));
    TumImageEntry entry;
    entry.stamp_ns = NanosecondsFromSeconds(fields[0], where);
    entry.stamp_text = std::string(fields[0]);
    // The name ends up in messages about the image; one with control bytes is no TUM file name.
    if (std::any_of(fields[1].begin(), fields[1].end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7F; }))
      throw InputError(where, Str("file name ", QuoteForMessage(fields[1]), " contains control characters"));
    entry.relative_path = std::string(fields[1]);
    entry.line = line_number;
    entry.exists = std::filesystem::is_regular_file(sequence_dir / entry.relative_path);
    if (!list.entries.empty() && entry.stamp_ns < list.entries.back().stamp_ns)
      throw InputError(where, "timestamps go backwards (the list must be sorted by time)");
    list.entries.push_back(std::move(entry));
  }
  return list;
}

TumGroundTruth ReadTumGroundTruth(const std::filesystem::path& file) {
  const std::string text = ReadTextFile(file);
  TumGroundTruth gt;
  gt.file = file;
  const auto lines = SplitLines(text);
  for (size_t i = 0; i < lines.size(); ++i) {
    if (IsComment(lines[i])) continue;
    const std::string where = Where(file, static_cast<int64_t>(i + 1));
    const auto f = SplitWhitespace(lines[i]);
    if (!StartsWithDigit(f[0]) && gt.samples.empty()) continue;  // header that lost its '#'
    if (f.size() != 8)
      throw InputError(where, Str("expected 'timestamp tx ty tz qx qy qz qw' (8 fields), got ", f.size()));
    double v[7];
    for (int k = 0; k < 7; ++k) v[k] = ParseDouble(f[k + 1], where);
    PoseSample sample;
    sample.stamp_ns = NanosecondsFromSeconds(f[0], where);
    sample.status = PoseStatus::kValid;
    // TUM quaternions are scalar-last (qx qy qz qw).
    sample.pose = Rigid3d(QuaternionNearlyUnit(v[6], v[3], v[4], v[5], where), Eigen::Vector3d(v[0], v[1], v[2]));
    if (!gt.samples.empty()) {
      if (sample.stamp_ns < gt.samples.back().stamp_ns)
        throw InputError(where, "timestamps go backwards (groundtruth.txt must be sorted by time)");
      if (sample.stamp_ns == gt.samples.back().stamp_ns) ++gt.duplicate_stamps;
    }
    gt.samples.push_back(sample);
    gt.stamp_texts.emplace_back(f[0]);
  }
  return gt;
}

void TumAssociationOptions::check() const {
  if (max_difference_ns <= 0) throw InputError("TumAssociationOptions", "max_difference_ns must be positive");
}

std::vector<TumAssociation> AssociateTum(const std::vector<int64_t>& first_ns, const std::vector<int64_t>& second_ns,
                                         const TumAssociationOptions& options) {
  options.check();
  // Candidate pairs within the window; both lists are sorted, so a sliding start index suffices.
  std::vector<TumAssociation> candidates;
  size_t start = 0;
  for (size_t a = 0; a < first_ns.size(); ++a) {
    while (start < second_ns.size() && second_ns[start] + options.offset_ns <= first_ns[a] - options.max_difference_ns)
      ++start;
    for (size_t b = start; b < second_ns.size(); ++b) {
      const int64_t diff = first_ns[a] - (second_ns[b] + options.offset_ns);
      if (diff <= -options.max_difference_ns) break;
      candidates.push_back({a, b, diff < 0 ? -diff : diff});
    }
  }
  // Nearest first; ties as Python's tuple sort (difference, a, b).
  std::sort(candidates.begin(), candidates.end(), [&](const TumAssociation& x, const TumAssociation& y) {
    return std::tie(x.difference_ns, first_ns[x.first], second_ns[x.second]) <
           std::tie(y.difference_ns, first_ns[y.first], second_ns[y.second]);
  });
  std::vector<bool> used_first(first_ns.size(), false), used_second(second_ns.size(), false);
  std::vector<TumAssociation> matches;
  for (const auto& c : candidates) {
    if (used_first[c.first] || used_second[c.second]) continue;
    used_first[c.first] = used_second[c.second] = true;
    matches.push_back(c);
  }
  std::sort(matches.begin(), matches.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  return matches;
}

PinholeCamera TumCamera(TumCameraPreset preset) {
  PinholeCamera camera;
  camera.width = 640;
  camera.height = 480;
  switch (preset) {
    case TumCameraPreset::kFreiburg1:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::tuple(517.3, 516.5, 318.6, 255.3);
      camera.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
      break;
    case TumCameraPreset::kFreiburg2:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::tuple(520.9, 521.0, 325.1, 249.7);
      camera.dist = {0.2312, -0.7849, -0.0033, -0.0001, 0.9172, 0, 0, 0};
      break;
    case TumCameraPreset::kFreiburg3:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::tuple(535.4, 539.2, 320.1, 247.6);
      break;
    case TumCameraPreset::kRosDefault:
      std::tie(camera.fx, camera.fy, camera.cx, camera.cy) = std::tuple(525.0, 525.0, 319.5, 239.5);
      break;
  }
  return camera;
}

std::optional<TumCameraPreset> TumPresetFromBagName(const std::string& bag_name) {
  if (bag_name.find("freiburg1") != std::string::npos) return TumCameraPreset::kFreiburg1;
  if (bag_name.find("freiburg2") != std::string::npos) return TumCameraPreset::kFreiburg2;
  if (bag_name.find("freiburg3") != std::string::npos) return TumCameraPreset::kFreiburg3;
  return std::nullopt;
}

TumCameraPreset TumPresetFromName(const std::string& name) {
  if (name == "fr1") return TumCameraPreset::kFreiburg1;
  if (name == "fr2") return TumCameraPreset::kFreiburg2;
  if (name == "fr3") return TumCameraPreset::kFreiburg3;
  if (name == "ros") return TumCameraPreset::kRosDefault;
  throw InputError("--intrinsics", Str("unknown camera preset ", QuoteForMessage(name), " (fr1, fr2, fr3, ros or fx,fy,cx,cy)"));
}

TumSequence ReadTumSequence(const std::filesystem::path& dir, const TumAssociationOptions& options) {
  if (!std::filesystem::is_directory(dir)) throw InputError(dir.string(), "not a folder (expected a TUM sequence)");
  TumSequence seq;
  seq.dir = dir;
  seq.rgb = ReadTumImageList(dir / "rgb.txt", dir);
  seq.depth = ReadTumImageList(dir / "depth.txt", dir);
  seq.groundtruth = ReadTumGroundTruth(dir / "groundtruth.txt");
  std::vector<int64_t> rgb_ns, depth_ns;
  for (const auto& e : seq.rgb.entries) rgb_ns.push_back(e.stamp_ns);
  for (const auto& e : seq.depth.entries) depth_ns.push_back(e.stamp_ns);
  seq.rgb_depth = AssociateTum(rgb_ns, depth_ns, options);
  return seq;
}

}  // namespace mocap::import
