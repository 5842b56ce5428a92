// LoadDataset: the inputs of an export read through the pipeline's run readers, checked to belong
// together (docs/export.md "Inputs").
#include <map>
#include <system_error>

#include "core/check.h"
#include "exporters/dataset/selection.h"
#include "label/pose_chain.h"
#include "pipeline/provenance.h"
#include "pipeline/rig.h"
#include "pipeline/validation_run.h"

namespace mocap::exporters {
namespace fs = std::filesystem;
namespace {

bool SamePath(const fs::path& a, const fs::path& b) {
  std::error_code error;
  return fs::equivalent(a, b, error) && !error;
}

/// Adds `library`'s objects to `merged`: one id per name across sessions, or an InputError naming both
/// files (`source`: object name -> the file it came from).
void MergeObjects(const pipeline::ObjectLibrary& library, pipeline::ObjectLibrary& merged,
                  std::map<std::string, fs::path>& source) {
  for (const pipeline::LibraryObject& object : library.objects) {
    const pipeline::LibraryObject* by_name = merged.Find(object.name);
    const pipeline::LibraryObject* by_id = merged.FindId(object.id);
    if (by_name && by_name->id == object.id) continue;
    if (by_name || by_id) {
      const pipeline::LibraryObject& other = by_name ? *by_name : *by_id;
      throw InputError(library.file.string(),
                       Str("object '", object.name, "' has id ", object.id, " here but ", source[other.name].string(),
                           " gives '", other.name, "' id ", other.id,
                           ": a dataset needs one id per object across its sessions (edit one objects.yaml)"));
    }
    merged.objects.push_back(object);
    source[object.name] = library.file;
  }
}

fs::path FindValidationRun(const ExportInput& input, const fs::path& session_dir) {
  if (input.ignore_validation) return {};
  if (!input.validation_dir.empty()) return fs::absolute(input.validation_dir);
  const fs::path guess = session_dir / "validation";
  return fs::exists(guess / "validation.json") ? guess : fs::path();
}

/// The validator's records by (camera, index, instance).
using CheckKey = std::tuple<std::string, int64_t, int>;
std::map<CheckKey, const RecordCheck*> IndexChecks(const pipeline::ValidationRun& run) {
  std::map<CheckKey, const RecordCheck*> checks;
  for (const RecordCheck& c : run.records) checks[{c.camera, c.index, c.instance}] = &c;
  return checks;
}

void CheckLabelRunOfSession(const pipeline::LabelRun& labels, const fs::path& session_dir) {
  const fs::path manifest = labels.layout.manifest_json();
  const std::string recorded = labels.manifest.value("session", std::string());
  if (recorded.empty() || !SamePath(recorded, session_dir))
    throw InputError(manifest.string(), Str("this label run was made from session '", recorded, "', not '",
                                            session_dir.string(), "' (give the session's own label run with --labels)"));
}

void CheckValidationOfLabels(const pipeline::ValidationRun& validation, const fs::path& labels_dir) {
  const std::string recorded = validation.summary.value("labels", std::string());
  if (recorded.empty() || !SamePath(recorded, labels_dir))
    throw InputError(validation.layout.summary_json().string(),
                     Str("this validation run checked label run '", recorded, "', not '", labels_dir.string(), "'"));
}

/// `rig_camera`: the label run's rig entry for the camera; its T_color_depth replaces the device's.
ExportScene MakeScene(const CameraStreamInfo& info, const PinholeCamera& color_camera, const LabelRigCamera* rig_camera) {
  ExportScene scene;
  scene.camera = info.name;
  scene.camera_model = info.model;
  scene.color_camera = color_camera;
  scene.depth_camera = info.depth_registered_to_color ? color_camera : info.depth_camera;
  scene.T_color_depth = rig_camera && rig_camera->T_color_depth ? *rig_camera->T_color_depth : info.T_color_depth;
  scene.depth_registered_to_color = info.depth_registered_to_color;
  scene.depth_unit_m = info.depth_unit_m;
  return scene;
}

/// Whether a label without a pose means the object is not there (ExportInstance::absent).
bool KnownAbsent(const SessionReader& session, const pipeline::LabelRecord& r) {
  if (r.reason.rfind("no tracker in the session reports", 0) == 0) return true;
  const auto tracker = session.TrackerOfBody(r.body);
  const TrackerStreamInfo* info = tracker ? session.manifest().FindTracker(*tracker) : nullptr;
  return info != nullptr && info->frame.rfind("camera:", 0) == 0;
}

/// The frames of one camera of a label run, with their instances, verdicts and camera poses.
void AddFrames(Dataset& dataset, size_t scene_index, const pipeline::LabelRun& labels, const PoseChain& chain,
               const std::map<CheckKey, const RecordCheck*>& checks) {
  const ExportScene& scene = dataset.scenes[scene_index];
  ExportFrame* current = nullptr;
  for (const pipeline::LabelRecord& r : labels.records) {
    if (r.camera != scene.camera) continue;
    if (current == nullptr || current->index != r.index) {
      ExportFrame& f = dataset.frames.emplace_back();
      f.scene = scene_index, f.index = r.index, f.frame = r.frame, f.stamp_ns = r.stamp_ns;
      f.color_path = scene.session->ColorPath(scene.camera, r.index);
      f.depth_path = scene.session->DepthPath(scene.camera, r.index);
      f.T_tracker_camera = chain.TrackerCameraPose(r.stamp_ns);
      current = &f;
    }
    ExportInstance& instance = current->instances.emplace_back();
    instance.record = r;
    instance.absent = !r.has_pose && KnownAbsent(*scene.session, r);
    if (const auto it = checks.find({r.camera, r.index, r.instance}); it != checks.end()) {
      const LabelCheck& c = it->second->check;
      instance.has_check = true;
      instance.verdict = std::string(ToString(c.verdict));
      instance.verdict_reason = c.reason;
      if (c.estimated) instance.check_error_mm = c.errors.position_mm, instance.check_error_deg = c.errors.rotation_angle_deg;
    }
  }
}

void AddInput(Dataset& dataset, const ExportInput& input, std::map<std::string, fs::path>& object_source) {
  const fs::path session_dir = fs::absolute(input.session_dir).lexically_normal();
  const fs::path labels_dir = fs::absolute(input.labels_dir.empty() ? session_dir / "labels" : input.labels_dir);
  auto session = std::make_shared<const SessionReader>(SessionReader::Open(session_dir));
  const pipeline::LabelRun labels = pipeline::LabelRun::Read(labels_dir);
  CheckLabelRunOfSession(labels, session_dir);
  const pipeline::RunProvenance run = pipeline::ReadRunJson(labels_dir);
  const fs::path objects_file = pipeline::RecordedInput(run, "objects"), rig_file = pipeline::RecordedInput(run, "rig");
  if (objects_file.empty())
    throw InputError((labels_dir / "run.json").string(), "names no object library (role 'objects')");
  MergeObjects(pipeline::ReadObjectLibrary(objects_file), dataset.objects, object_source);
  const LabelRig rig = rig_file.empty() ? LabelRig{} : pipeline::LabelRigOf(pipeline::ReadRig(rig_file));

  std::optional<pipeline::ValidationRun> validation;
  const fs::path validation_dir = FindValidationRun(input, session_dir);
  if (!validation_dir.empty()) {
    validation = pipeline::ValidationRun::Read(validation_dir);
    CheckValidationOfLabels(*validation, labels_dir);
  }
  const auto checks = validation ? IndexChecks(*validation) : std::map<CheckKey, const RecordCheck*>{};

  dataset.inputs.emplace_back("session", session_dir);
  dataset.inputs.emplace_back("labels", labels_dir);
  if (validation) dataset.inputs.emplace_back("validation", validation_dir);
  dataset.inputs.emplace_back("objects", objects_file);
  for (const nlohmann::json& camera : labels.manifest.at("cameras")) {
    const std::string name = camera.get<std::string>();
    const CameraStreamInfo* info = session->manifest().FindCamera(name);
    if (info == nullptr)
      throw InputError(labels.layout.manifest_json().string(), Str("camera '", name, "' is not in the session"));
    const PoseChain chain(*session, name, {}, rig);
    ExportScene scene = MakeScene(*info, chain.camera(), rig.Find(name));
    scene.scene_id = static_cast<int>(dataset.scenes.size()) + 1;
    scene.name = session_dir.filename().string() + "/" + name;
    scene.session_dir = session_dir, scene.labels_dir = labels_dir, scene.validation_dir = validation_dir;
    scene.labels = labels.layout;
    scene.session = session;
    dataset.scenes.push_back(std::move(scene));
    AddFrames(dataset, dataset.scenes.size() - 1, labels, chain, checks);
  }
}

}  // namespace

Dataset LoadDataset(const std::vector<ExportInput>& inputs) {
  if (inputs.empty()) throw InputError("export", "no session given");
  Dataset dataset;
  std::map<std::string, fs::path> object_source;
  for (const ExportInput& input : inputs) {
    for (const auto& [role, path] : dataset.inputs)
      if (role == "session" && SamePath(path, input.session_dir))
        throw InputError(input.session_dir.string(), "the session is given twice");
    AddInput(dataset, input, object_source);
  }
  return dataset;
}

}  // namespace mocap::exporters
