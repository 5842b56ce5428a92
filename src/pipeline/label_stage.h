#pragma once
// `mocaplabel label` as a library call and as a pipeline stage: read the session, the rig and the object
// library, label, write the label run (label_run.h) into <out>.partial with its run.json, publish it.
#include <filesystem>
#include <string>
#include <vector>

#include "label/labeller.h"
#include "pipeline/run_provenance.h"
#include "pipeline/stage.h"
#include "session/reader.h"

namespace mocap::pipeline {

struct LabelRunRequest {
  std::filesystem::path session_dir;
  std::filesystem::path rig_file;      ///< empty: the calibration recorded in the session
  std::filesystem::path objects_file;  ///< empty: the session's own objects.yaml
  std::filesystem::path out_dir;
  LabelOptions label;
  Shard shard;                         ///< a frame range: label.frame_begin/end are set from it
  std::vector<std::string> command;    ///< recorded in run.json
  ProgressSink* progress = nullptr;
};

struct LabelRunResult {
  LabelSummary summary;
  std::filesystem::path out_dir;
};

/// The object library a command uses: `objects_flag`, else SESSION/objects.yaml; InputError when neither.
std::filesystem::path FindObjectsFile(const std::filesystem::path& session_dir, const std::filesystem::path& objects_flag);

/// Throws InputError for bad inputs (the files named), an unusable output folder or a failed write;
/// the output is then left in <out>.partial, never at <out>.
LabelRunResult RunLabel(const LabelRunRequest& request);

/// The labeller into a label run at `out`, published whole (what RunLabel does once it has read its
/// inputs; for callers that hold the objects and rig in memory).
/// run.json records the session, every mesh and `record`'s inputs (the rig and objects files).
LabelSummary WriteLabelRun(const SessionReader& session, const std::vector<LabelObject>& objects, const LabelRig& rig,
                           const LabelOptions& options, const std::filesystem::path& out, const RunRecord& record = {});

/// label_manifest.json of a finished run.
nlohmann::json LabelManifestJson(const LabelSummary& summary, const std::filesystem::path& session_dir,
                                 const std::filesystem::path& out_dir);

/// The label stage: labels context.session_dir with context.rig_file and context.objects_file into
/// context.out_dir/labels (sets context.labels_dir, results["label"], outputs["labels"]).
Stage MakeLabelStage(const LabelOptions& options);

}  // namespace mocap::pipeline
