#pragma once
// Test and benchmark shorthands over the pipeline: label runs of objects and rigs built in memory, and
// BOP imports whose objects.yaml the pipeline's writer writes (as `mocaplabel import bop` does).
#include <filesystem>
#include <vector>

#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/validate_stage.h"
#include "pipeline/validation_run.h"
#include "session/import/bop_import.h"

namespace mocap {

/// LabelOptions with the folder the label run goes to.
struct LabelRunOptions : LabelOptions {
  std::filesystem::path out_dir;
};

/// The labeller into a label run at options.out_dir (pipeline::WriteLabelRun).
inline LabelSummary LabelSession(const SessionReader& session, const std::vector<LabelObject>& objects,
                                 const LabelRig& rig, const LabelRunOptions& options) {
  return pipeline::WriteLabelRun(session, objects, rig, options, options.out_dir);
}

/// The labeller's view of an objects.yaml.
inline std::vector<LabelObject> ReadLabelObjects(const std::filesystem::path& file) {
  return pipeline::LabelObjectsOf(pipeline::ReadObjectLibrary(file));
}

inline import::BopImportOptions BopOptions() {
  import::BopImportOptions options;
  options.write_objects = pipeline::WriteBopObjects;
  return options;
}

/// The validator's view of an objects.yaml.
inline std::vector<ValidationObject> ReadValidationObjects(const std::filesystem::path& file) {
  return pipeline::ValidationObjectsOf(pipeline::ReadObjectLibrary(file));
}

/// The records and file paths of the label run at `labels_dir`, as the validator takes them.
inline LabelRunView ReadLabelRecords(const std::filesystem::path& labels_dir) {
  return pipeline::LabelRunViewOf(pipeline::LabelRun::Read(labels_dir));
}

/// CheckSession on the label run at options.labels_dir.
inline SessionValidation CheckSession(const SessionReader& session, const std::vector<ValidationObject>& objects,
                                      const SessionCheckOptions& options) {
  return CheckSession(session, objects, ReadLabelRecords(options.labels_dir), options);
}

/// CheckSession, then the validation run published at `out`.
inline SessionValidation ValidateSession(const SessionReader& session, const std::vector<ValidationObject>& objects,
                                         const SessionCheckOptions& options, const std::filesystem::path& out) {
  return pipeline::ValidateIntoRun(session, objects, ReadLabelRecords(options.labels_dir), options, out);
}

}  // namespace mocap
