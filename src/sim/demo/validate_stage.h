#pragma once
// The demo's validation stage: the SegICP session check (`mocaplabel validate`, docs/validation.md) on
// the demo's session and labels, written to OUT/validation.
#include <vector>

#include "sim/demo/demo_pipeline.h"
#include "validate/session_check.h"

namespace mocap::sim {

/// The validator's objects of a recording labelled with `calibration`: meshes as the labeller's, and
/// the library's continuous symmetries (the funnel's axis) so that estimates are compared modulo them.
std::vector<ValidationObject> ValidationObjects(const RecordResult& record, const ObjectLibrary& library,
                                                const RigCalibration& calibration);

/// Runs ValidateSession on c.record's session with c.labels_dir, checking every
/// c.options.validate_frame_stride-th frame; fills segicp_success_rate, verdicts, validated_frames and
/// outputs["validation"]. Needs the record and label stages before it.
void ValidateStage(DemoContext& c);

}  // namespace mocap::sim
