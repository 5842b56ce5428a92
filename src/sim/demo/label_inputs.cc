#include "sim/demo/label_inputs.h"

#include "core/check.h"

namespace mocap::sim {

LabelInputs MakeLabelInputs(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration) {
  namespace fs = std::filesystem;
  LabelInputs inputs;
  inputs.rig.name = "sim";
  inputs.rig.tracker_latency_ns = calibration.tracker_latency_ns;
  inputs.rig.cameras.push_back({record.camera_name, calibration.color_camera, record.camera_body, calibration.T_cambody_camera});
  for (size_t i = 0; i < calibration.objects.size(); ++i) {
    const ObjectSpec* spec = library.Find(calibration.objects[i]);
    MOCAP_CHECK(spec, "calibration names an object not in the library: ", calibration.objects[i]);
    LabelObject object;
    object.id = spec->id;
    object.name = spec->name;
    object.object_class = spec->object_class.empty() ? spec->name : spec->object_class;
    object.mesh_path = fs::absolute(record.library_dir / spec->mesh);
    object.unit_scale_to_m = spec->unit_scale_to_m;
    object.mounts.push_back({spec->body.name, calibration.T_objbody_mesh[i]});
    inputs.objects.push_back(object);
  }
  return inputs;
}

}  // namespace mocap::sim
