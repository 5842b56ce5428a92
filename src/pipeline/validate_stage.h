#pragma once
// `mocaplabel validate` as a library call and as a pipeline stage: the SegICP session check of a label
// run against the session's measured depth, written as a validation run (validation_run.h) into
// <out>.partial with its run.json, then published.
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/run_provenance.h"
#include "pipeline/session_wide.h"
#include "pipeline/stage.h"
#include "session/reader.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

struct ValidateRunRequest {
  std::filesystem::path session_dir, labels_dir;
  std::filesystem::path objects_file;  ///< empty: the session's own objects.yaml
  std::filesystem::path out_dir;
  SessionCheckOptions check;           ///< labels_dir is set from above
  Shard shard;
  /// Objects left out like skipped frames (by name), or all but `only_object_names` when that is not
  /// empty; a name the object library does not have is an InputError.
  std::vector<std::string> skip_object_names, only_object_names;
  /// After the per-record checks, the session-wide step (session_wide.h); a shard leaves it to the merge.
  SessionWideOptions session_wide;
  std::vector<std::string> command;
  ProgressSink* progress = nullptr;
};

/// Throws InputError for bad inputs, an unusable output folder or a failed write (the output then stays
/// in <out>.partial).
SessionValidation RunValidate(const ValidateRunRequest& request);

/// CheckSession, then the validation run written into <out>.partial and published (RunValidate once it
/// has read its inputs; for callers that hold the objects in memory).
/// run.json records the session, the label run, every mesh and `record`'s inputs. The session-wide step
/// runs after the checks unless `options` name a frame range (a shard: the merge runs it).
SessionValidation ValidateIntoRun(const SessionReader& session, const std::vector<ValidationObject>& objects,
                                  LabelRunView labels, const SessionCheckOptions& options, const std::filesystem::path& out,
                                  const RunRecord& record = {}, const SessionWideOptions& session_wide = {});

/// The validate stage: checks context.labels_dir against context.session_dir into
/// context.out_dir/validation, every `frame_stride`-th frame, leaving out `skip_objects` (names).
Stage MakeValidateStage(int frame_stride, std::vector<std::string> skip_objects);

}  // namespace mocap::pipeline
