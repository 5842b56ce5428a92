#pragma once
// What each kind of run records in its run.json (docs/provenance.md "Inputs each run kind records"): the
// inputs of label and validation runs, the options as JSON, and the one call that fingerprints the
// inputs and writes run.json into a run folder before it is published.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "label/labeller.h"
#include "pipeline/object_library.h"
#include "pipeline/provenance.h"
#include "session/manifest.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

/// A session as an input: its manifest and stream files (session/manifest.h SessionStreamFiles). The
/// images are not hashed: the writer never rewrites one, and a re-recording writes new stream files.
InputSpec SessionInput(const std::filesystem::path& session_dir);
/// "mesh:<name>" for each object's mesh file.
std::vector<InputSpec> MeshInputs(const std::vector<LabelObject>& objects);
std::vector<InputSpec> MeshInputs(const std::vector<ValidationObject>& objects);
/// A run folder another run read (a validation run's label run), every file of it.
InputSpec RunFolderInput(const std::string& role, const std::filesystem::path& dir);

/// The options a run used, for run.json (what changes the output; not threads or the EGL platform).
nlohmann::json ToJson(const LabelOptions& options);
nlohmann::json ToJson(const SessionCheckOptions& options);
/// The options back from a run.json (strict: a missing or mistyped field is an InputError naming
/// `where` and the field), so that a run can be redone as it was made (relabel).
LabelOptions LabelOptionsFromJson(const nlohmann::json& json, const std::string& where);
SessionCheckOptions SessionCheckOptionsFromJson(const nlohmann::json& json, const std::string& where);

/// {object name: digest of its objects.yaml entry} for the library's objects that a tracker of the
/// session reports a body of: what a label or validation run of that session depends on in the library.
/// A run records it (options `objects_in_session`) so that editing another object's entry does not
/// make it stale (docs/relabel.md). The mesh file is not in the digest: it is an input of its own.
nlohmann::json ObjectsInSession(const ObjectLibrary& library, const SessionManifest& manifest);

/// What a command adds to a run's provenance: its argv, the input files it read besides those the run
/// derives itself (the session, the meshes), and the shard it ran over.
struct RunRecord {
  std::vector<std::string> command;
  std::vector<InputSpec> inputs;
  nlohmann::json shard = nullptr;
  nlohmann::json objects_in_session = nullptr;  ///< ObjectsInSession; null: not recorded
};

/// Fingerprints `inputs` (through the hash cache) and writes `dir`/run.json.
void WriteProvenance(const std::filesystem::path& dir, const std::string& kind, const std::vector<std::string>& command,
                     const nlohmann::json& options, const std::vector<InputSpec>& inputs,
                     const nlohmann::json& shard = nullptr);
/// `options` with record.objects_in_session added (when recorded), as run.json holds them.
nlohmann::json RecordedOptions(nlohmann::json options, const RunRecord& record);

}  // namespace mocap::pipeline
