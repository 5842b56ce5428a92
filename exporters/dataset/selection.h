#pragma once
// Reading the inputs of an export and choosing what goes in (docs/export.md "Filters" and "Splits"):
// LoadDataset reads each session's label run (and validation run) through the pipeline's readers, checks
// they belong together, merges the object libraries, then keeps the frames and instances the filters
// pass and assigns each frame a split.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "exporters/dataset/dataset.h"

namespace mocap::exporters {

struct ExportFilterOptions {
  /// Validator verdicts kept; "unchecked" stands for labels the validator did not check (or sessions
  /// without a validation run). Default: everything but `reject`.
  std::vector<std::string> verdicts = {"accept", "suspect", "unchecked"};
  /// Label flags that leave a label out (labels.md "Flags"); "all" = every flag. Default: every flag
  /// (gap, missing_body, out_of_volume, fast_motion, no_pose, unreadable_depth, ...).
  std::vector<std::string> drop_flags = {"all"};
  /// A frame where a label that shows in the image (or has no pose, so may show) is left out by the
  /// verdict or flag filter is left out whole: otherwise it would show an object without its label.
  /// false: leave out only that instance.
  bool drop_frame_with_bad_label = true;
  /// Instances whose visible fraction is below this are left out (not the frame). 0 keeps all.
  double min_visib_fract = 0.0;
  /// Keep a frame only when the camera or some kept object moved this far (mm or deg, relative to the
  /// camera) since the last kept frame of its scene; 0 and 0 = off.
  double min_motion_mm = 0.0, min_motion_deg = 0.0;
  int every_nth = 1;  ///< keep every Nth frame of a scene (after the other filters)
  void check() const;
};

enum class SplitBy { kNone, kSession, kTime };

struct ExportSplitOptions {
  SplitBy by = SplitBy::kTime;
  /// Fractions of frames for train, val and test (sum 1).
  double train = 0.8, val = 0.1, test = 0.1;
  /// kTime: each scene is cut into blocks this long, blocks shuffled into the splits (seeded).
  double block_s = 10.0;
  /// kTime: frames closer than this to a frame of another split are left out (no near duplicates
  /// across splits).
  double guard_s = 1.0;
  uint64_t seed = 1;
  std::string none_split = "train";  ///< kNone: where every frame goes
  void check() const;
};

/// What each filter removed, for the summary.
struct SelectionSummary {
  int64_t frames_in = 0, frames_kept = 0;
  int64_t instances_in = 0, instances_kept = 0;
  /// reason ("verdict reject", "flag gap", "no masks", "visib_fract < 0.1", "min motion", "every nth",
  /// "guard gap", "frame with a left-out label") -> count of frames or instances.
  std::map<std::string, int64_t> frames_removed, instances_removed;
  std::map<std::string, int64_t> frames_per_split;
  std::map<std::string, int64_t> instances_per_object;  ///< kept, by object name
};

/// Reads the inputs: each session, its label run (ExportInput::labels_dir or SESSION/labels) and its
/// validation run (given, or SESSION/validation when finished there). Throws InputError (naming the
/// file) for a label run that is missing, unfinished or made from another session, a validation run of
/// another label run, an object whose id or name clashes between sessions' libraries, or a camera whose
/// intrinsics cannot be found. No filter applied: every labelled frame, every instance.
Dataset LoadDataset(const std::vector<ExportInput>& inputs);

/// Gives every frame its split (ExportSplitOptions) and, for time splits, leaves out the frames within
/// the guard gap of a frame of an earlier split (train before val before test), counted in `summary`.
void AssignSplits(Dataset& dataset, const ExportSplitOptions& options, SelectionSummary& summary);

/// Applies the filters, gives each kept frame its im_id (its camera record index) and assigns splits.
SelectionSummary SelectFrames(Dataset& dataset, const ExportFilterOptions& filters, const ExportSplitOptions& splits);

}  // namespace mocap::exporters
