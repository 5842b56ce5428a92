#pragma once
// bench_validate_session's figures: the accuracy of one session check against the truth, per object and in
// all, and the tables it prints (markdown, as bench/RESULTS.md records them).
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "pipeline/label_run.h"
#include "validate/session_check.h"

namespace mocap::bench {

/// Median and 95th percentile.
struct Spread {
  double median = 0, p95 = 0;
};

/// Over the records whose input could be checked (no bad-input verdict), as the session check tests count.
struct Accuracy {
  int64_t checked = 0, accepted = 0, success = 0;
  Spread position_mm, rotation_deg;  ///< the estimate against the truth, over the records with an estimate
};

/// One backend's run of a case.
struct BackendRun {
  std::string backend;
  int64_t records = 0;  ///< with a pose
  double wall_s = 0, cpu_s = 0, point_to_point_s = 0, point_to_plane_s = 0;
  Accuracy all;
  std::map<std::string, Accuracy> per_object;
};

/// Reading the frames and making the scene clouds, replayed alone (CPU seconds).
struct ReplayedSteps {
  double io_s = 0, scene_cloud_s = 0;
};

/// Fills run->all and run->per_object. The truth is a simulated session's truth/poses.jsonl (`truth_dir`),
/// matched by the labels' simulated frame; without one, each record's label is the truth (LM-O's labels
/// are its ground truth).
void ScoreRun(const SessionValidation& validation, const pipeline::LabelRun& labels, const std::filesystem::path& truth_dir,
              BackendRun* run);

/// The case's tables: per backend the speed, the CPU shares and the accuracy, the ratios to the first
/// backend, then the accuracy per object.
void PrintCase(const std::string& name, const ReplayedSteps& steps, const std::vector<BackendRun>& runs);

}  // namespace mocap::bench
