// Splits (docs/export.md "Splits"): by session, or by contiguous time blocks with a guard gap, so that
// no split holds near duplicates of another's frames (30 Hz frames of one scene differ by millimetres:
// frames shuffled one by one into train and test leak, the classic mistake of real-data sets).
#include <algorithm>
#include <cmath>
#include <random>

#include "core/check.h"
#include "exporters/dataset/selection.h"

namespace mocap::exporters {
namespace fs = std::filesystem;
namespace {

const char* const kSplits[] = {"train", "val", "test"};

/// Fisher-Yates with our own index draw: std::shuffle's distribution is implementation-defined, and a
/// seed must give the same split on every machine.
template <typename T>
void SeededShuffle(std::vector<T>& items, uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (size_t i = items.size(); i > 1; --i) std::swap(items[i - 1], items[rng() % i]);
}

/// Assigns groups (each a list of frame indices) in the given order: train until its share of the
/// frames is reached, then val, then test.
void FillSplits(const std::vector<std::vector<size_t>>& groups, const ExportSplitOptions& o, std::vector<ExportFrame>& frames) {
  size_t total = 0;
  for (const auto& g : groups) total += g.size();
  const double bounds[] = {o.train, o.train + o.val, 1.0};
  size_t done = 0;
  for (const auto& group : groups) {
    const double position = (static_cast<double>(done) + 0.5 * static_cast<double>(group.size())) / static_cast<double>(total);
    int split = 0;
    while (split < 2 && position >= bounds[split]) ++split;
    for (size_t i : group) frames[i].split = kSplits[split];
    done += group.size();
  }
}

void SplitBySession(Dataset& d, const ExportSplitOptions& o) {
  std::vector<fs::path> sessions;
  for (const ExportScene& scene : d.scenes)
    if (std::find(sessions.begin(), sessions.end(), scene.session_dir) == sessions.end()) sessions.push_back(scene.session_dir);
  SeededShuffle(sessions, o.seed);
  std::vector<std::vector<size_t>> groups(sessions.size());
  for (size_t i = 0; i < d.frames.size(); ++i) {
    const auto at = std::find(sessions.begin(), sessions.end(), d.scene_of(d.frames[i]).session_dir);
    groups[static_cast<size_t>(at - sessions.begin())].push_back(i);
  }
  FillSplits(groups, o, d.frames);
}

void SplitByTime(Dataset& d, const ExportSplitOptions& o) {
  std::map<std::pair<size_t, int64_t>, std::vector<size_t>> blocks;  // (scene, block) -> frames
  std::map<size_t, int64_t> first_stamp;
  for (size_t i = 0; i < d.frames.size(); ++i) first_stamp.try_emplace(d.frames[i].scene, d.frames[i].stamp_ns);
  const double block_ns = o.block_s * 1e9;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    const ExportFrame& f = d.frames[i];
    const auto block = static_cast<int64_t>(std::floor(static_cast<double>(f.stamp_ns - first_stamp[f.scene]) / block_ns));
    blocks[{f.scene, block}].push_back(i);
  }
  std::vector<std::vector<size_t>> groups;
  for (auto& [key, frames] : blocks) groups.push_back(std::move(frames));
  SeededShuffle(groups, o.seed);
  FillSplits(groups, o, d.frames);
}

int Rank(const std::string& split) {
  for (int i = 0; i < 3; ++i)
    if (split == kSplits[i]) return i;
  return 3;
}

/// Leaves out each frame within guard_s of a frame of an earlier split of the same scene, so the
/// earlier split keeps all its frames and the gap between any two splits is at least guard_s.
void ApplyGuard(Dataset& d, const ExportSplitOptions& o, SelectionSummary& s) {
  const auto guard_ns = static_cast<int64_t>(std::llround(o.guard_s * 1e9));
  // Frames are in scene order, and in stamp order within a scene: look only at neighbours in the gap.
  auto near_earlier_split = [&](size_t i, long step) {
    const ExportFrame& f = d.frames[i];
    for (long j = static_cast<long>(i) + step; j >= 0 && j < static_cast<long>(d.frames.size()); j += step) {
      const ExportFrame& g = d.frames[static_cast<size_t>(j)];
      if (g.scene != f.scene || std::llabs(g.stamp_ns - f.stamp_ns) >= guard_ns) return false;
      if (Rank(g.split) < Rank(f.split)) return true;
    }
    return false;
  };
  std::vector<bool> drop(d.frames.size(), false);
  for (size_t i = 0; i < d.frames.size(); ++i) drop[i] = near_earlier_split(i, -1) || near_earlier_split(i, +1);
  std::vector<ExportFrame> kept;
  for (size_t i = 0; i < d.frames.size(); ++i) {
    if (drop[i]) ++s.frames_removed["guard gap"];
    else kept.push_back(std::move(d.frames[i]));
  }
  d.frames = std::move(kept);
}

}  // namespace

void ExportSplitOptions::check() const {
  const std::string where = "ExportSplitOptions";
  if (!(train >= 0 && val >= 0 && test >= 0) || std::abs(train + val + test - 1.0) > 1e-6)
    throw InputError(where, Str("split fractions must be >= 0 and sum to 1 (train ", train, ", val ", val, ", test ", test, ")"));
  if (!(block_s > 0)) throw InputError(where, "block_s must be positive");
  if (!(guard_s >= 0)) throw InputError(where, "guard_s must be >= 0");
  if (Rank(none_split) > 2) throw InputError(where, Str("unknown split '", none_split, "' (train, val, test)"));
}

void AssignSplits(Dataset& dataset, const ExportSplitOptions& o, SelectionSummary& summary) {
  if (o.by == SplitBy::kNone) {
    for (ExportFrame& f : dataset.frames) f.split = o.none_split;
    return;
  }
  if (o.by == SplitBy::kSession) SplitBySession(dataset, o);
  else SplitByTime(dataset, o);
  if (o.by == SplitBy::kTime && o.guard_s > 0) ApplyGuard(dataset, o, summary);
}

}  // namespace mocap::exporters
