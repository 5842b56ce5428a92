#pragma once
// The demo's `capture` stage (docs/demo.md): the simulated session, recorded by `sim record`, is
// played through the capture daemon in real time (capture/daemon/rerecord.h: its tracker stream
// served by an NDI emulator on loopback and read by the daemon's NDI source, its camera stream by a
// session replay source) into OUT/session, which the later stages label, validate and score. It lives in
// the CLI because it joins two modules of which neither may depend on the other's layer (sim, capture).
#include "sim/demo/demo_pipeline.h"

namespace mocap::cli {

/// Needs the record stage before it. Throws InputError when the daemon's session is not complete (a
/// write error); dropped frames are not an error: they show in `dropped_frames` and `capture`.
sim::DemoStage DemoCaptureStage();

/// DefaultDemoStages() with DemoCaptureStage() after `record`.
std::vector<sim::DemoStage> DemoStagesThroughDaemon();

}  // namespace mocap::cli
