// SelectFrames: the filters and splits of docs/export.md, in the order documented there.
#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "core/check.h"
#include "exporters/dataset/selection.h"

namespace mocap::exporters {
namespace {

bool Contains(const std::vector<std::string>& list, const std::string& item) {
  return std::find(list.begin(), list.end(), item) != list.end();
}

/// Why the verdict or flag filters leave a label out ("" when they keep it).
std::string BadLabelReason(const ExportInstance& instance, const ExportFilterOptions& o) {
  const std::string verdict = instance.has_check ? instance.verdict : "unchecked";
  if (!Contains(o.verdicts, verdict)) return "verdict " + verdict;
  const bool all = Contains(o.drop_flags, "all");
  for (const std::string& flag : instance.record.flags)
    if (all || Contains(o.drop_flags, flag)) return "flag " + flag;
  if (!instance.record.has_pose) return "no pose";
  return "";
}

/// Applies the per-label filters to one frame; returns the reason the whole frame goes ("" to keep it).
std::string FilterInstances(ExportFrame& frame, const ExportFilterOptions& o, SelectionSummary& s) {
  std::vector<ExportInstance> kept;
  for (ExportInstance& instance : frame.instances) {
    const pipeline::LabelRecord& r = instance.record;
    if (instance.absent) {
      ++s.instances_removed["object not in the frame"];
      continue;
    }
    if (const std::string why = BadLabelReason(instance, o); !why.empty()) {
      if (o.drop_frame_with_bad_label && (!r.has_pose || r.px_count_visib > 0)) return "a label left out: " + why;
      ++s.instances_removed[why];
      continue;
    }
    if (r.visib_fract < o.min_visib_fract) {
      ++s.instances_removed[Str("visib_fract < ", o.min_visib_fract)];
      continue;
    }
    kept.push_back(std::move(instance));
  }
  frame.instances = std::move(kept);
  return "";
}

bool MovedEnough(const Rigid3d& a, const Rigid3d& b, const ExportFilterOptions& o) {
  return (o.min_motion_mm > 0 && TranslationDistanceM(a, b) * 1e3 >= o.min_motion_mm) ||
         (o.min_motion_deg > 0 && RotationDistanceDeg(a, b) >= o.min_motion_deg);
}

/// Whether `frame` differs enough from the last kept frame of its scene: the camera moved, an object
/// moved relative to the camera, or an object came or went.
bool MovedSince(const ExportFrame& frame, const ExportFrame& last, const ExportFilterOptions& o) {
  if (frame.T_tracker_camera && last.T_tracker_camera && MovedEnough(*frame.T_tracker_camera, *last.T_tracker_camera, o))
    return true;
  if (frame.instances.size() != last.instances.size()) return true;
  for (size_t i = 0; i < frame.instances.size(); ++i) {
    const pipeline::LabelRecord &a = frame.instances[i].record, &b = last.instances[i].record;
    if (a.instance != b.instance || MovedEnough(a.T_camera_mesh(), b.T_camera_mesh(), o)) return true;
  }
  return false;
}

/// The filters: per label, then motion and every-Nth per scene. Returns the frames kept.
std::vector<ExportFrame> Filter(std::vector<ExportFrame> frames, const ExportFilterOptions& o, SelectionSummary& s) {
  std::vector<ExportFrame> kept;
  std::map<size_t, const ExportFrame*> last_kept;  // by scene (pointers into `kept`: reserved below)
  std::map<size_t, int64_t> count_in_scene;
  kept.reserve(frames.size());
  const bool motion = o.min_motion_mm > 0 || o.min_motion_deg > 0;
  for (ExportFrame& frame : frames) {
    if (const std::string why = FilterInstances(frame, o, s); !why.empty()) {
      ++s.frames_removed[why];
      continue;
    }
    const auto last = last_kept.find(frame.scene);
    if (motion && last != last_kept.end() && !MovedSince(frame, *last->second, o)) {
      ++s.frames_removed["min motion"];
      continue;
    }
    if (count_in_scene[frame.scene]++ % o.every_nth != 0) {
      ++s.frames_removed["every nth"];
      continue;
    }
    kept.push_back(std::move(frame));
    last_kept[kept.back().scene] = &kept.back();
  }
  return kept;
}

}  // namespace

void ExportFilterOptions::check() const {
  const std::string where = "ExportFilterOptions";
  for (const std::string& v : verdicts)
    if (v != "accept" && v != "suspect" && v != "reject" && v != "unchecked")
      throw InputError(where, Str("unknown verdict '", v, "' (accept, suspect, reject, unchecked)"));
  if (!(min_visib_fract >= 0 && min_visib_fract <= 1)) throw InputError(where, "min_visib_fract must be in 0..1");
  if (!(min_motion_mm >= 0) || !(min_motion_deg >= 0)) throw InputError(where, "minimum motions must be >= 0");
  if (every_nth < 1) throw InputError(where, "every_nth must be >= 1");
}

SelectionSummary SelectFrames(Dataset& dataset, const ExportFilterOptions& filters, const ExportSplitOptions& splits) {
  filters.check();
  splits.check();
  SelectionSummary s;
  s.frames_in = static_cast<int64_t>(dataset.frames.size());
  for (const ExportFrame& f : dataset.frames) s.instances_in += static_cast<int64_t>(f.instances.size());
  dataset.frames = Filter(std::move(dataset.frames), filters, s);
  AssignSplits(dataset, splits, s);
  for (ExportFrame& f : dataset.frames) {
    f.im_id = static_cast<int>(f.index);  // stable whatever the filters keep: a frame keeps its id across exports
    ++s.frames_per_split[f.split];
    s.instances_kept += static_cast<int64_t>(f.instances.size());
    for (const ExportInstance& i : f.instances) ++s.instances_per_object[i.record.name];
  }
  s.frames_kept = static_cast<int64_t>(dataset.frames.size());
  return s;
}

}  // namespace mocap::exporters
