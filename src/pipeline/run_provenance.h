#pragma once
// What each kind of run records in its run.json (docs/provenance.md "Inputs each run kind records"): the
// inputs of label and validation runs, the options as JSON, and the one call that fingerprints the
// inputs and writes run.json into a run folder before it is published.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "label/labeller.h"
#include "pipeline/provenance.h"
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

/// What a command adds to a run's provenance: its argv, the input files it read besides those the run
/// derives itself (the session, the meshes), and the shard it ran over.
struct RunRecord {
  std::vector<std::string> command;
  std::vector<InputSpec> inputs;
  nlohmann::json shard = nullptr;
};

/// Fingerprints `inputs` (through the hash cache) and writes `dir`/run.json.
void WriteProvenance(const std::filesystem::path& dir, const std::string& kind, const std::vector<std::string>& command,
                     const nlohmann::json& options, const std::vector<InputSpec>& inputs,
                     const nlohmann::json& shard = nullptr);

}  // namespace mocap::pipeline
