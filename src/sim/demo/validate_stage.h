#pragma once
// The demo's validation stage: the SegICP session check (`mocaplabel validate`, docs/validation.md) on
// the demo's session and labels, written to OUT/validation.
#include "sim/demo/demo_pipeline.h"

namespace mocap::sim {

/// Runs ValidateSession on c.record's session with c.labels_dir, checking every
/// c.options.validate_frame_stride-th frame; fills segicp_success_rate, verdicts, validated_frames and
/// outputs["validation"]. Needs the record and label stages before it.
void ValidateStage(DemoContext& c);

}  // namespace mocap::sim
