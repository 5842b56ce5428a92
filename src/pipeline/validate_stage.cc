#include "pipeline/validate_stage.h"

#include <algorithm>
#include <set>

#include "core/check.h"
#include "pipeline/label_run.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/provenance.h"
#include "pipeline/publish.h"
#include "pipeline/rig.h"
#include "pipeline/validation_run.h"
#include "session/reader.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

/// The ids of the objects the request leaves out (`--skip-objects`, or all but `--objects-only`).
std::vector<int> SkippedObjectIds(const ValidateRunRequest& request, const ObjectLibrary& library) {
  for (const std::vector<std::string>* names : {&request.skip_object_names, &request.only_object_names})
    for (const std::string& name : *names)
      if (!library.Find(name)) throw InputError(library.file.string(), "has no object '" + name + "' (named to validate or leave out)");
  std::vector<int> ids;
  for (const LibraryObject& o : library.objects) {
    const auto named = [&](const std::vector<std::string>& names) { return std::ranges::count(names, o.name) > 0; };
    if (named(request.skip_object_names) || (!request.only_object_names.empty() && !named(request.only_object_names)))
      ids.push_back(o.id);
  }
  return ids;
}

}  // namespace

SessionValidation RunValidate(const ValidateRunRequest& request) {
  const SessionReader session = SessionReader::Open(request.session_dir);
  const LabelRun labels = LabelRun::Read(request.labels_dir);
  const fs::path objects_file = FindObjectsFile(request.session_dir, request.objects_file);
  const ObjectLibrary library = ReadObjectLibrary(objects_file);
  SessionCheckOptions options = request.check;
  options.labels_dir = request.labels_dir;
  options.frame_begin = request.shard.begin;
  options.frame_end = request.shard.end;
  if (request.progress) options.progress = request.progress;
  for (int id : SkippedObjectIds(request, library)) options.skip_objects.push_back(id);
  // A depth-to-colour transform the label run's rig calibrated replaces the session's, as for the labels.
  const fs::path rig_file = fs::exists(request.labels_dir / "run.json")
                                ? RecordedInput(ReadRunJson(request.labels_dir), "rig") : fs::path();
  if (fs::is_regular_file(rig_file))
    for (const LabelRigCamera& camera : LabelRigOf(ReadRig(rig_file)).cameras)
      if (camera.T_color_depth) options.T_color_depth.emplace(camera.camera, *camera.T_color_depth);
  const RunRecord record{request.command, {{"objects", objects_file, false, {}}}, request.shard.ToJson(),
                         ObjectsInSession(library, session.manifest())};
  return ValidateIntoRun(session, ValidationObjectsOf(library), LabelRunViewOf(labels, request.shard.begin, request.shard.end),
                         options, request.out_dir, record, request.session_wide);
}

SessionValidation ValidateIntoRun(const SessionReader& session, const std::vector<ValidationObject>& objects,
                                  LabelRunView labels, const SessionCheckOptions& options, const fs::path& out,
                                  const RunRecord& record, const SessionWideOptions& session_wide) {
  options.check();
  session_wide.check();
  PartialOutput output(out, "validation.json", "validation");
  SessionValidation validation = CheckSession(session, objects, std::move(labels), options);
  const bool shard = options.frame_begin != 0 || options.frame_end != -1;
  if (session_wide.enabled && !shard) FlagSessionWideErrors(validation, objects, session_wide);
  std::vector<InputSpec> inputs = {SessionInput(session.dir()), RunFolderInput("labels", options.labels_dir)};
  inputs.insert(inputs.end(), record.inputs.begin(), record.inputs.end());
  for (InputSpec& mesh : MeshInputs(objects)) inputs.push_back(std::move(mesh));
  nlohmann::json recorded = ToJson(options);
  recorded["session_wide"] = session_wide.enabled;
  WriteProvenance(output.dir(), "validation", record.command, RecordedOptions(std::move(recorded), record), inputs, record.shard);
  WriteValidationRun(validation, options, session.dir(), output.dir(), out);
  output.Publish();
  return validation;
}

Stage MakeValidateStage(int frame_stride, std::vector<std::string> skip_objects) {
  Stage stage;
  stage.name = "validate";
  stage.inputs = [](const PipelineContext& c) { return std::vector<fs::path>{c.session_dir, c.labels_dir, c.objects_file}; };
  stage.outputs = [](const PipelineContext& c) { return std::vector<fs::path>{c.out_dir / "validation"}; };
  stage.run = [frame_stride, skip_objects](PipelineContext& c, const Shard& shard) {
    ValidateRunRequest request;
    request.session_dir = c.session_dir, request.labels_dir = c.labels_dir, request.objects_file = c.objects_file;
    request.out_dir = c.out_dir / "validation";
    request.check.threads = c.threads;
    request.check.frame_stride = frame_stride;
    request.check.context = c.render_context;
    request.shard = shard;
    request.skip_object_names = skip_objects;
    request.command = c.command;
    request.progress = c.progress;
    const SessionValidation v = RunValidate(request);
    std::set<std::pair<std::string, int64_t>> frames;
    for (const RecordCheck& r : v.records) frames.insert({r.camera, r.index});
    nlohmann::json& result = c.results["validate"];
    result = {{"validated_frames", frames.size()}, {"frame_stride", frame_stride}, {"verdicts", v.summary.verdicts},
              {"records_checked", v.summary.records_checked}};
    // No checkable record (e.g. every object out of view) leaves the rate unset rather than a false 0.
    result["segicp_success_rate"] = v.summary.records_checked > 0 ? nlohmann::json(v.summary.segicp_success_rate) : nlohmann::json();
    c.validation_dir = request.out_dir;
    c.outputs["validation"] = request.out_dir.string();
    std::string skipped;
    for (const std::string& name : skip_objects) skipped += (skipped.empty() ? "" : ", ") + name;
    if (!skipped.empty()) c.notes.push_back("validation leaves out " + skipped);
    if (frame_stride > 1)
      c.notes.push_back(Str("validation checked one frame in ", frame_stride, " (", frames.size(),
                            " frames) to keep the demo short; `mocaplabel validate` checks every frame"));
  };
  return stage;
}

}  // namespace mocap::pipeline
