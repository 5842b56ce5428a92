#include "sim/demo/validate_stage.h"

#include <set>

#include "core/check.h"
#include "validate/validation_output.h"

namespace mocap::sim {

std::vector<ValidationObject> ValidationObjects(const RecordResult& record, const ObjectLibrary& library,
                                                const RigCalibration& calibration) {
  std::vector<ValidationObject> objects;
  for (const LabelObject& o : MakeLabelInputs(record, library, calibration).objects) {
    std::vector<SymmetryAxis> symmetries;
    for (const Symmetry& s : library.Find(o.name)->symmetries)
      symmetries.push_back({s.axis, s.offset_m, s.type == Symmetry::Type::kContinuous ? 0.0 : s.angle_deg});
    objects.push_back({o.id, o.name, o.mesh_path, o.unit_scale_to_m, ChooseValidatorSymmetry(symmetries)});
  }
  return objects;
}

void ValidateStage(DemoContext& c) {
  MOCAP_CHECK(!c.labels_dir.empty(), "the validation stage needs the label stage before it");
  const std::vector<ValidationObject> objects = ValidationObjects(c.record, c.library, c.record.truth.given_calibration);
  SessionCheckOptions options;
  options.labels_dir = c.labels_dir;
  options.threads = c.options.threads;
  options.frame_stride = c.options.validate_frame_stride;
  // A table top is a plane: the measured depth does not constrain its in-plane position, so SegICP
  // slides along it and cannot verify the label, and its large mesh makes it the slowest check.
  for (const ValidationObject& o : objects)
    if (o.name == "table") options.skip_objects.push_back(o.id);
  options.context = c.options.context;
  const std::filesystem::path out = c.options.out_dir / "validation";
  const SessionValidation v = ValidateSession(SessionReader::Open(c.record.session_dir), objects, options, out);
  std::set<std::pair<std::string, int64_t>> frames;
  for (const RecordCheck& r : v.records) frames.insert({r.camera, r.index});
  c.validated_frames = static_cast<int64_t>(frames.size());
  c.validate_frame_stride = options.frame_stride;
  // No checkable record (e.g. every object out of view) leaves the rate unset rather than a false 0.
  if (v.summary.records_checked > 0) c.segicp_success_rate = v.summary.segicp_success_rate;
  c.verdicts = v.summary.verdicts;
  c.outputs["validation"] = out.string();
  if (!options.skip_objects.empty()) c.notes.push_back("validation leaves out the table (a plane: not verifiable by ICP)");
  if (options.frame_stride > 1)
    c.notes.push_back(Str("validation checked one frame in ", options.frame_stride, " (", c.validated_frames,
                          " frames) to keep the demo short; `mocaplabel validate` checks every frame"));
}

}  // namespace mocap::sim
