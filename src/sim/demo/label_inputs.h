#pragma once
// What the labeller is handed for a simulated recording, built in process from the calibration (the
// same content as the rig.yaml and objects.yaml that `sim record` writes for the command line).
#include <filesystem>
#include <vector>

#include "label/label_objects.h"
#include "label/rig.h"
#include "sim/record/sim_recorder.h"

namespace mocap::sim {

struct LabelInputs {
  Rig rig;
  std::vector<LabelObject> objects;
};

/// Rig and objects for `calibration` (true or given) of a recording. Mesh paths are those of
/// `record.objects_file`'s library, resolved against the session folder.
LabelInputs MakeLabelInputs(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration);

}  // namespace mocap::sim
