#include "pipeline/label_stage.h"

#include "core/check.h"
#include "pipeline/label_run.h"
#include "pipeline/object_library.h"
#include "pipeline/publish.h"
#include "pipeline/rig.h"
#include "session/reader.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

nlohmann::json StagesJson(const LabelStageSeconds& s) {
  return {{"render", s.render}, {"read_depth", s.read_depth}, {"labels", s.labels}, {"write", s.write}};
}

nlohmann::json CullingJson(const std::vector<ObjectCulling>& culling) {
  nlohmann::json j = nlohmann::json::array();
  for (const ObjectCulling& c : culling) j.push_back({{"object", c.object}, {"culled", c.culled}, {"reason", c.reason}});
  return j;
}

}  // namespace

fs::path FindObjectsFile(const fs::path& session_dir, const fs::path& objects_flag) {
  if (!objects_flag.empty()) return objects_flag;
  if (fs::exists(session_dir / "objects.yaml")) return session_dir / "objects.yaml";
  throw InputError(session_dir.string(), "the session carries no objects.yaml; pass --objects (e.g. meshes/objects.yaml)");
}

nlohmann::json LabelManifestJson(const LabelSummary& s, const fs::path& session_dir, const fs::path& out_dir) {
  return {{"session", fs::absolute(session_dir).lexically_normal().string()},
          {"out", fs::absolute(out_dir).lexically_normal().string()},
          {"complete", true},
          {"cameras", s.cameras},
          {"frames", s.frames},
          {"frames_skipped", s.frames_skipped},
          {"records", s.records},
          {"records_with_pose", s.records_with_pose},
          {"frames_flagged", s.frames_flagged},
          {"flag_counts", s.flag_counts},
          {"seconds", s.seconds},
          {"setup_seconds", s.setup_seconds},
          {"frames_seconds", s.frames_seconds},
          {"frames_cpu_seconds", s.frames_cpu_seconds},
          {"render_seconds", s.render_seconds},
          {"threads", s.threads},
          {"back_face_culling", CullingJson(s.culling)},
          {"stage_seconds", StagesJson(s.stages)},
          {"stage_cpu_seconds", StagesJson(s.stages_cpu)}};
}

/// A rig camera the session does not have would be ignored and the recorded calibration used: a typo
/// in a camera name must not silently undo a calibration fix.
static void CheckRigCameras(const Rig& rig, const SessionReader& session) {
  std::string names;
  for (const CameraStreamInfo& c : session.manifest().cameras) names += (names.empty() ? "" : ", ") + c.name;
  for (const RigCameraCalibration& c : rig.cameras)
    if (!session.manifest().FindCamera(c.name))
      throw InputError(rig.file.string(), Str("camera '", c.name, "' is not in the session ", session.dir().string(),
                                              " (its cameras: ", names.empty() ? "none" : names, ")"));
}

LabelRunResult RunLabel(const LabelRunRequest& request) {
  const SessionReader session = SessionReader::Open(request.session_dir);
  LabelRig rig;
  if (!request.rig_file.empty()) {
    const Rig file = ReadRig(request.rig_file);
    CheckRigCameras(file, session);
    rig = LabelRigOf(file);
  }
  const fs::path objects_file = FindObjectsFile(request.session_dir, request.objects_file);
  const ObjectLibrary library = ReadObjectLibrary(objects_file);
  LabelOptions options = request.label;
  options.frame_begin = request.shard.begin;
  options.frame_end = request.shard.end;
  if (request.progress) options.progress = request.progress;
  RunRecord record{request.command, {{"objects", objects_file, false, {}}}, request.shard.ToJson(),
                   ObjectsInSession(library, session.manifest())};
  if (!request.rig_file.empty()) record.inputs.push_back({"rig", request.rig_file, false, {}});
  LabelRunResult result;
  result.summary = WriteLabelRun(session, LabelObjectsOf(library), rig, options, request.out_dir, record);
  result.out_dir = request.out_dir;
  return result;
}

LabelSummary WriteLabelRun(const SessionReader& session, const std::vector<LabelObject>& objects, const LabelRig& rig,
                           const LabelOptions& options, const fs::path& out, const RunRecord& record) {
  options.check();
  PartialOutput output(out, "label_manifest.json", "label");
  LabelRunWriter writer(output.dir());
  const LabelSummary summary = LabelSession(session, objects, rig, options, writer);
  std::vector<InputSpec> inputs = {SessionInput(session.dir())};
  inputs.insert(inputs.end(), record.inputs.begin(), record.inputs.end());
  for (InputSpec& mesh : MeshInputs(objects)) inputs.push_back(std::move(mesh));
  WriteProvenance(output.dir(), "label", record.command, RecordedOptions(ToJson(options), record), inputs, record.shard);
  writer.Finish(LabelManifestJson(summary, session.dir(), out));
  output.Publish();
  return summary;
}

Stage MakeLabelStage(const LabelOptions& options) {
  Stage stage;
  stage.name = "label";
  stage.inputs = [](const PipelineContext& c) { return std::vector<fs::path>{c.session_dir, c.rig_file, c.objects_file}; };
  stage.outputs = [](const PipelineContext& c) { return std::vector<fs::path>{c.out_dir / "labels"}; };
  stage.run = [options](PipelineContext& c, const Shard& shard) {
    LabelRunRequest request{c.session_dir, c.rig_file, c.objects_file, c.out_dir / "labels", options, shard, c.command, c.progress};
    request.label.threads = c.threads;
    request.label.context = c.render_context;
    const LabelRunResult result = RunLabel(request);
    c.labels_dir = result.out_dir;
    c.results["label"] = LabelManifestJson(result.summary, c.session_dir, result.out_dir);
    c.outputs["labels"] = result.out_dir.string();
  };
  return stage;
}

}  // namespace mocap::pipeline
