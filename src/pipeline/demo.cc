#include "pipeline/demo.h"

#include <fstream>

#include "core/check.h"
#include "pipeline/contact_sheet.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/publish.h"
#include "pipeline/record_stage.h"
#include "pipeline/rig.h"
#include "pipeline/run_provenance.h"
#include "pipeline/visible_masks.h"
#include "pipeline/yaml_write.h"
#include "session/reader.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

/// Scores a label run; the label's visible masks use the measured depth where it is registered.
LabelScores Score(const PipelineContext& c) {
  const SessionReader session = SessionReader::Open(c.session_dir);
  const Rig rig = ReadRig(c.rig_file);
  const RigCameraCalibration* calibrated = rig.Find(c.camera);
  const PinholeCamera camera = calibrated && calibrated->intrinsics ? *calibrated->intrinsics
                                                                     : session.manifest().FindCamera(c.camera)->color_camera;
  VisibleMaskRenderer masks(LabelObjectsOf(ReadObjectLibrary(c.objects_file)), camera, c.render_context);
  return ScoreLabels(c.labels_dir, c.truth_dir, &session, &masks);
}

LabelOptions DemoLabelOptions() {
  LabelOptions label;
  label.output.write_masks = true;  // the export's masks (scoring and the contact sheet need the instance images only)
  label.output.write_depth = false;
  label.renderer.outside_margin_fraction = 0.25;  // amodal boxes of objects leaving the image are not scored
  return label;
}

nlohmann::json ScoresJson(const LabelScores& s) {
  return {{"frames", s.frames},
          {"records", s.records},
          {"records_without_pose", s.records_without_pose},
          {"mask_iou_mean", s.mask_iou_mean},
          {"mask_iou_p5", s.mask_iou_p5},
          {"mask_iou_model_mean", s.mask_iou_model_mean},
          {"mask_iou_model_p5", s.mask_iou_model_p5},
          {"pose_err_mm_median", s.pose_err_mm_median},
          {"pose_err_mm_p95", s.pose_err_mm_p95},
          {"pose_err_deg_median", s.pose_err_deg_median},
          {"pose_err_deg_p95", s.pose_err_deg_p95}};
}

nlohmann::json Field(const PipelineContext& c, const char* stage, const char* key) {
  const auto it = c.results.find(stage);
  return it != c.results.end() && it->second.contains(key) ? it->second[key] : nlohmann::json();
}

nlohmann::json DemoJson(const PipelineContext& c, const StageSeconds& stage_seconds, int expected_frames,
                        const std::string& scenario) {
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& [stage, s] : stage_seconds) seconds[stage] = s;
  nlohmann::json j = {{"complete", true}, {"scenario", scenario}};
  const nlohmann::json scores = c.results.count("score") ? c.results.at("score") : nlohmann::json::object();
  for (const auto& [key, value] : scores.items()) j[key] = value;
  j["dropped_frames"] = expected_frames - scores.value("frames", int64_t{0});
  j["flagged_frames"] = Field(c, "label", "frames_flagged");
  j["segicp_success_rate"] = Field(c, "validate", "segicp_success_rate");
  j["verdicts"] = Field(c, "validate", "verdicts");
  j["validated_frames"] = Field(c, "validate", "validated_frames");
  j["validate_frame_stride"] = Field(c, "validate", "frame_stride");
  j["capture"] = c.results.count("capture") ? c.results.at("capture") : nlohmann::json();
  j["export"] = c.results.count("export") ? c.results.at("export") : nlohmann::json();
  j["seconds_per_stage"] = seconds;
  j["outputs"] = c.outputs;
  j["notes"] = c.notes;
  return j;
}

}  // namespace

void DemoOptions::check() const {
  if (out_dir.empty()) throw InputError("demo", "no output folder given (--out)");
  if (frames < 0) throw InputError("demo", "--frames must be >= 0");
  if (threads < 0) throw InputError("demo", "--threads must be >= 0");
  if (validate_frame_stride < 1) throw InputError("demo", "--validate-every must be >= 1");
  context.check();
}

Stage MakeScoreStage() {
  Stage stage;
  stage.name = "score";
  stage.inputs = [](const PipelineContext& c) { return std::vector<fs::path>{c.labels_dir, c.truth_dir, c.session_dir}; };
  stage.run = [](PipelineContext& c, const Shard&) { c.results["score"] = ScoresJson(Score(c)); };
  return stage;
}

Stage MakeContactSheetStage() {
  Stage stage;
  stage.name = "contact_sheet";
  stage.inputs = [](const PipelineContext& c) { return std::vector<fs::path>{c.labels_dir, c.session_dir}; };
  stage.run = [](PipelineContext& c, const Shard&) {
    const fs::path png = c.out_dir / "contact_sheet.png";
    WriteContactSheet(SessionReader::Open(c.session_dir), c.camera, c.labels_dir, png);
    c.outputs["contact_sheet"] = png.string();
  };
  return stage;
}

Stage MakeDemoLabelStage() { return MakeLabelStage(DemoLabelOptions()); }

LabelSummary LabelRecording(const sim::RecordResult& record, const sim::RigCalibration& calibration,
                            const fs::path& labels_dir, const DemoOptions& options) {
  fs::path inputs = labels_dir;
  inputs += ".inputs";
  const CalibrationFiles files = WriteCalibrationFiles(record, BuiltInLibraryOf(record), calibration, "sim", inputs);
  LabelRunRequest request{record.session_dir, files.rig, files.objects, labels_dir, DemoLabelOptions(), {}, {}, nullptr};
  request.label.threads = options.threads;
  request.label.context = options.context;
  return RunLabel(request).summary;
}

LabelScores LabelAndScore(const sim::RecordResult& record, const sim::RigCalibration& calibration,
                          const fs::path& labels_dir, const DemoOptions& options) {
  LabelRecording(record, calibration, labels_dir, options);
  PipelineContext c;
  c.session_dir = record.session_dir, c.labels_dir = labels_dir, c.truth_dir = record.truth_dir;
  c.camera = record.camera_name, c.render_context = options.context;
  fs::path inputs = labels_dir;
  inputs += ".inputs";
  c.rig_file = inputs / "rig.yaml", c.objects_file = inputs / "objects.yaml";
  return Score(c);
}

sim::Scenario DemoScenario(const sim::Scenario& scenario, const DemoOptions& options) {
  sim::Scenario s = scenario;
  if (options.frames > 0) s.options.frame_count = std::min(options.frames, scenario.options.frame_count);
  return s;
}

DemoResult RunDemo(const DemoOptions& options, const std::vector<Stage>& stages, int expected_frames,
                   const std::string& scenario_name, std::vector<std::string> command) {
  options.check();
  PartialOutput output(options.out_dir, "demo.json", "demo");
  DemoResult result;
  PipelineContext& c = result.context;
  c.out_dir = output.dir();
  c.threads = options.threads;
  c.render_context = options.context;
  c.progress = options.progress;
  c.command = std::move(command);
  result.seconds_per_stage = RunStages(stages, c);
  if (!c.results.count("capture")) c.notes.push_back("recorded with the session writer directly (no capture stage ran)");
  result.summary = DemoJson(c, result.seconds_per_stage, expected_frames, scenario_name);
  WriteProvenance(output.dir(), "demo", c.command,
                  {{"scenario", scenario_name}, {"frames", expected_frames}, {"validate_frame_stride", options.validate_frame_stride}},
                  {});
  WriteTextAtomically(output.dir() / "demo.json", result.summary.dump(2) + "\n");
  output.Publish();  // also rewrites the paths in demo.json to the published folder
  result.summary = nlohmann::json::parse(std::ifstream(options.out_dir / "demo.json"));
  return result;
}

}  // namespace mocap::pipeline
