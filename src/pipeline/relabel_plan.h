#pragma once
// Relabel's plan (docs/relabel.md): for every session, which of its runs (SESSION/labels,
// SESSION/validation) are stale against the inputs they would read now, and why; and the shards of the
// work to redo. Staleness is provenance.h's CheckStale with one refinement: a run records the digests of
// the objects.yaml entries of the objects its session holds (run_provenance.h ObjectsInSession), so an
// edit of another object's entry or mesh does not stale it. A stale run is redone with the options it
// recorded, so that an unchanged input gives the same bytes.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "label/labeller.h"
#include "pipeline/hash_cache.h"
#include "pipeline/stage.h"
#include "session/manifest.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

struct RelabelPlanOptions {
  std::filesystem::path rig_file;      ///< empty: each run's recorded rig (or the session's calibration)
  std::filesystem::path objects_file;  ///< empty: each run's recorded library, else SESSION/objects.yaml
  bool label = true, validate = true;  ///< the stages asked for
  /// Frames per shard; 0: a session is one shard. The merged run is the one a single pass writes.
  int64_t shard_frames = 0;
  /// A session whose runs name another folder (it was moved or copied): relabel it rather than refuse.
  bool relabel_moved = false;
  LabelOptions label_options;          ///< for a session without a label run yet
  SessionCheckOptions check_options;   ///< for a session without a validation run yet
  void check() const;                  ///< InputError for a negative shard size or no stage
};

struct StagePlan {
  bool run = false;
  std::vector<std::string> why;  ///< one line per reason it is stale ("no label run yet", ...)
  nlohmann::json options;        ///< what it runs with, as run.json records options
  std::vector<Shard> shards;     ///< every shard of the run (one whole-session shard: no merge)
  std::vector<int> todo;         ///< indexes into `shards` still to run; finished shards are kept
};

struct SessionPlan {
  std::filesystem::path session_dir, rig_file, objects_file, labels_dir, validation_dir;
  int64_t frames = 0;  ///< records of the longest camera stream
  StagePlan label, validate;
  bool merged(const StagePlan& stage) const { return stage.shards.size() > 1; }
  int64_t ShardFrames(const Shard& shard) const { return (shard.end < 0 ? frames : shard.end) - shard.begin; }
};

struct RelabelPlan {
  std::vector<SessionPlan> sessions;
  double seconds = 0;                         ///< planning time
  int64_t files_checked = 0, files_hashed = 0;  ///< by the staleness checks
  int64_t FramesToRun(bool validate) const;   ///< frames of the shards to run of one stage
};

/// Plans `sessions` (folders). InputError naming the file for a folder that is not a session, a run
/// without run.json, a run made by a newer mocaplabel, a run of another kind, or (unless
/// relabel_moved) a run whose session has moved.
RelabelPlan PlanRelabel(const std::vector<std::filesystem::path>& sessions, const RelabelPlanOptions& options,
                        HashCache& cache);

nlohmann::json ToJson(const SessionPlan& session);
nlohmann::json ToJson(const RelabelPlan& plan);
/// Strict, for the plan file the executors' tasks read.
RelabelPlan RelabelPlanFromJson(const nlohmann::json& json, const std::string& where);

/// The number of records in the longest camera stream of the session (lines of frames.jsonl).
int64_t SessionFrames(const std::filesystem::path& session_dir);
int64_t SessionFrames(const std::filesystem::path& session_dir, const SessionManifest& manifest);

}  // namespace mocap::pipeline
