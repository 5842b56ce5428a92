#pragma once
// An 8-frame simulated session (the default scenario: Kinect v1 depth in mm, a tracked camera, bottle,
// funnel, engine block and table, a hand) and its label run with masks, made in process.
#include <filesystem>
#include <string>

#include "pipeline/label_stage.h"
#include "pipeline/record_stage.h"
#include "sim/scenario.h"
#include "tests/labeller/labeller_test_util.h"

namespace mocap::testing {

struct SimulatedLabels {
  std::filesystem::path dir, session, labels;
};

inline SimulatedLabels SimulateAndLabel(const std::string& name, int frames = 8) {
  SimulatedLabels out{FreshDir(name), {}, {}};
  out.session = out.dir / "S", out.labels = out.dir / "L";
  sim::Scenario scenario = sim::DefaultScenario();
  scenario.options.frame_count = frames;
  sim::RecordOptions record;
  record.out_dir = out.session, record.threads = 2;
  const pipeline::SimRecordResult recorded = pipeline::RecordSimulatedSession(scenario, nullptr, record);
  pipeline::LabelRunRequest request;
  request.session_dir = out.session, request.rig_file = recorded.rig_file, request.objects_file = recorded.objects_file;
  request.out_dir = out.labels, request.label.threads = 2, request.command = {"mocaplabel", "label"};
  pipeline::RunLabel(request);
  return out;
}

}  // namespace mocap::testing
