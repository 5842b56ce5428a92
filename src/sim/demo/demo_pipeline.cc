#include "sim/demo/demo_pipeline.h"

#include <chrono>

#include "core/check.h"
#include "session/reader.h"
#include "sim/demo/contact_sheet.h"
#include "sim/demo/validate_stage.h"
#include "sim/demo/visible_masks.h"
#include "sim/record/truth_io.h"

namespace mocap::sim {
namespace {

namespace fs = std::filesystem;

void RecordStage(DemoContext& c) {
  RecordOptions options;
  options.out_dir = c.options.out_dir / "simulated";
  options.threads = c.options.threads;
  options.context = c.options.context;
  c.record = RecordSimulation(c.scenario, c.library, {}, options);
  c.outputs["session"] = c.record.session_dir.string();
  c.outputs["truth"] = c.record.truth_dir.string();
  c.outputs["rig"] = c.record.rig_file.string();
  c.outputs["objects"] = c.record.objects_file.string();
}

void LabelStage(DemoContext& c) {
  c.labels_dir = c.options.out_dir / "labels";
  c.label = LabelRecording(c.record, c.library, c.record.truth.given_calibration, c.labels_dir, c.options);
  c.outputs["labels"] = c.labels_dir.string();
}

/// Scores a label run made with `calibration`; the label's visible masks use the measured depth.
LabelScores Score(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration,
                  const fs::path& labels_dir, const DemoOptions& options) {
  const SessionReader session = SessionReader::Open(record.session_dir);
  // The measured-depth visibility needs depth registered to the colour image (Kinect v1).
  if (!session.manifest().FindCamera(record.camera_name)->depth_registered_to_color)
    return ScoreLabels(labels_dir, record.truth_dir);
  const LabelInputs inputs = MakeLabelInputs(record, library, calibration);
  VisibleMaskRenderer masks(inputs.objects, calibration.color_camera, options.context);
  return ScoreLabels(labels_dir, record.truth_dir, &session, &masks);
}

void ScoreStage(DemoContext& c) {
  c.scores = Score(c.record, c.library, c.record.truth.given_calibration, c.labels_dir, c.options);
}

void ContactSheetStage(DemoContext& c) {
  const fs::path png = c.options.out_dir / "contact_sheet.png";
  WriteContactSheet(SessionReader::Open(c.record.session_dir), c.record.camera_name, c.labels_dir, png);
  c.outputs["contact_sheet"] = png.string();
}

void PrepareOutput(const fs::path& out) {
  if (fs::exists(out) && !fs::is_empty(out)) {
    if (!fs::exists(out / "demo.json"))
      throw InputError(out.string(), "exists and is not an earlier demo output (no demo.json); choose another --out");
    fs::remove_all(out);
  }
  fs::create_directories(out);
  // Marks the folder as the demo's at once, so a run that fails half-way can simply be repeated.
  WriteJsonFile(out / "demo.json", {{"complete", false}});
}

}  // namespace

void DemoOptions::check() const {
  if (out_dir.empty()) throw InputError("demo", "no output folder given (--out)");
  if (frames < 0) throw InputError("demo", "--frames must be >= 0");
  if (threads < 0) throw InputError("demo", "--threads must be >= 0");
  if (validate_frame_stride < 1) throw InputError("demo", "--validate-every must be >= 1");
  context.check();
}

std::vector<DemoStage> DefaultDemoStages() {
  return {{"record", RecordStage},
          {"label", LabelStage},
          {"validate", ValidateStage},
          {"score", ScoreStage},
          {"contact_sheet", ContactSheetStage}};
}

DemoResult RunDemo(const Scenario& scenario, const DemoOptions& options, const std::vector<DemoStage>& stages) {
  options.check();
  PrepareOutput(options.out_dir);
  DemoResult result;
  DemoContext& c = result.context;
  c.options = options;
  c.scenario = scenario;
  if (options.frames > 0) c.scenario.options.frame_count = std::min(options.frames, scenario.options.frame_count);
  c.library = DefaultObjectLibrary();
  for (const DemoStage& stage : stages) {
    const auto start = std::chrono::steady_clock::now();
    stage.run(c);
    result.seconds_per_stage.emplace_back(stage.name, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  if (c.capture.is_null()) c.notes.push_back("recorded with the session writer directly (no capture stage ran)");
  return result;
}

nlohmann::json DemoJson(const DemoResult& r) {
  const DemoContext& c = r.context;
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& [stage, s] : r.seconds_per_stage) seconds[stage] = s;
  const int expected = c.scenario.options.frame_count;
  return {{"complete", true},
          {"scenario", c.scenario.options.name},
          {"frames", c.scores.frames},
          {"dropped_frames", expected - c.scores.frames},
          {"mask_iou_mean", c.scores.mask_iou_mean},
          {"mask_iou_p5", c.scores.mask_iou_p5},
          {"mask_iou_model_mean", c.scores.mask_iou_model_mean},
          {"mask_iou_model_p5", c.scores.mask_iou_model_p5},
          {"pose_err_mm_median", c.scores.pose_err_mm_median},
          {"pose_err_mm_p95", c.scores.pose_err_mm_p95},
          {"pose_err_deg_median", c.scores.pose_err_deg_median},
          {"pose_err_deg_p95", c.scores.pose_err_deg_p95},
          {"flagged_frames", c.label.frames_flagged},
          {"records", c.scores.records},
          {"records_without_pose", c.scores.records_without_pose},
          {"segicp_success_rate", c.segicp_success_rate ? nlohmann::json(*c.segicp_success_rate) : nlohmann::json()},
          {"verdicts", c.verdicts},
          {"validated_frames", c.validate_frame_stride > 0 ? nlohmann::json(c.validated_frames) : nlohmann::json()},
          {"validate_frame_stride", c.validate_frame_stride > 0 ? nlohmann::json(c.validate_frame_stride) : nlohmann::json()},
          {"capture", c.capture},
          {"seconds_per_stage", seconds},
          {"outputs", c.outputs},
          {"notes", c.notes}};
}

LabelSummary LabelRecording(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration,
                            const fs::path& labels_dir, const DemoOptions& options) {
  const LabelInputs inputs = MakeLabelInputs(record, library, calibration);
  LabelOptions label;
  label.out_dir = labels_dir;
  label.threads = options.threads;
  label.context = options.context;
  label.output.write_masks = false;  // scoring and the contact sheet need the instance images only
  label.output.write_depth = false;
  label.renderer.outside_margin_fraction = 0.25;  // amodal boxes of objects leaving the image are not scored
  return LabelSession(SessionReader::Open(record.session_dir), inputs.objects, inputs.rig, label);
}

LabelScores LabelAndScore(const RecordResult& record, const ObjectLibrary& library, const RigCalibration& calibration,
                          const fs::path& labels_dir, const DemoOptions& options) {
  LabelRecording(record, library, calibration, labels_dir, options);
  return Score(record, library, calibration, labels_dir, options);
}

}  // namespace mocap::sim
