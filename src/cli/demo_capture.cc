#include "cli/demo_capture.h"

#include "capture/daemon/rerecord.h"
#include "core/check.h"

namespace mocap::cli {
namespace {

void CaptureStage(sim::DemoContext& c) {
  MOCAP_CHECK(!c.record.session_dir.empty(), "the capture stage needs the record stage before it");
  capture::RerecordOptions options;
  options.source_session = c.record.session_dir;
  options.out_session = c.options.out_dir / "session";
  const capture::RerecordResult r = capture::RerecordSession(options);
  if (!r.summary.value("complete", false))
    throw InputError(options.out_session.string(),
                     "the capture daemon did not complete the session: " + r.summary.value("error", std::string("unknown error")));
  c.outputs["simulated_session"] = c.record.session_dir.string();
  c.outputs["session"] = options.out_session.string();
  c.record.session_dir = options.out_session;
  c.capture = {{"source_frames", r.source_frames},
               {"recorded_frames", r.recorded_frames},
               {"dropped_frames", r.dropped_frames},
               {"late_frames", r.camera.value("late_frames", int64_t{0})},
               {"max_late_ms", r.camera.value("max_late_ms", 0.0)},
               {"tracker_rate_hz", r.tracker_rate_hz},
               {"tracker_poll_rate_hz", r.poll_rate_hz},
               {"tracker_frames", r.tracker.value("samples", int64_t{0})},
               {"tracker_crc_errors", r.tracker.value("crc_errors", int64_t{0})},
               {"streams", r.summary.at("streams")},
               {"seconds", r.seconds}};
  c.notes.push_back(Str("recorded through the capture daemon in real time: ", r.recorded_frames, " of ", r.source_frames,
                        " frames, tracker over NDI/TCP at ", r.tracker_rate_hz, " Hz polled at ", r.poll_rate_hz, " Hz"));
}

}  // namespace

sim::DemoStage DemoCaptureStage() { return {"capture", CaptureStage}; }

std::vector<sim::DemoStage> DemoStagesThroughDaemon() {
  std::vector<sim::DemoStage> stages = sim::DefaultDemoStages();
  MOCAP_CHECK(!stages.empty() && stages.front().name == "record", "the demo's first stage is not 'record'");
  stages.insert(stages.begin() + 1, DemoCaptureStage());
  return stages;
}

}  // namespace mocap::cli
