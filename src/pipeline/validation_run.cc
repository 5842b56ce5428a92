#include "pipeline/validation_run.h"

#include <Eigen/QR>
#include <cmath>
#include <fstream>

#include "core/check.h"
#include "pipeline/json_read.h"
#include "pipeline/yaml_write.h"
#include "validate/report_html.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json StatJson(const Stat& s) {
  return {{"count", s.count}, {"median", s.median}, {"p95", s.p95}, {"std", s.std}, {"max", s.max}};
}

std::string_view ToString(MaskValues values) { return values == MaskValues::kObjectId ? "object" : "instance"; }

/// The enum value whose ToString is the field's text; enumerates values from 0 up to `last`.
template <typename Enum>
Enum ParseEnum(const JsonFields& f, const char* key, Enum last) {
  const std::string text = f.String(key);
  for (int v = 0; v <= static_cast<int>(last); ++v)
    if (ToString(static_cast<Enum>(v)) == text) return static_cast<Enum>(v);
  throw InputError(f.where(), Str("field \"", key, "\" has an unknown value \"", text, "\""));
}

/// The directions the analysis judged, where it judged fewer than six (the calibration check measures
/// only these, calibrate/calibration_check.h): their analysis coordinates [L w; v] one after another, the
/// analysis centre (object frame) and L.
void WriteJudgedDirections(const Observability& o, nlohmann::json& j) {
  const Eigen::Matrix<double, 6, Eigen::Dynamic> judged = JudgedDirections(o);
  j["judged_directions"] = std::vector<double>(judged.data(), judged.data() + judged.size());
  j["analysis_center_m"] = Vec(o.center_object);
  j["analysis_radius_m"] = o.radius_m;
}

/// The judged directions first, the rest of the basis completed orthonormally (their information is not
/// kept). Each direction must be a unit vector.
void ReadJudgedDirections(const JsonFields& f, Observability* o) {
  const int m = o->observable;  // written as the count of the judged directions
  if (m < 0) throw InputError(f.where(), "observable_directions must be >= 0");
  const std::vector<double> judged = f.Numbers("judged_directions", static_cast<size_t>(6 * m));
  Eigen::Matrix<double, 6, Eigen::Dynamic> columns(6, m);
  for (int k = 0; k < m; ++k) {
    columns.col(k) = Eigen::Map<const Eigen::Matrix<double, 6, 1>>(judged.data() + 6 * k);
    if (std::abs(columns.col(k).norm() - 1.0) > 1e-6)
      throw InputError(f.where(), Str("judged_directions: direction ", k, " is not a unit vector"));
  }
  const Eigen::HouseholderQR<Eigen::Matrix<double, 6, Eigen::Dynamic>> qr(columns);
  o->directions = qr.householderQ() * Eigen::Matrix<double, 6, 6>::Identity();
  o->directions.leftCols(m) = columns;
  for (int k = 0; k < 6; ++k) o->judged[k] = k < m;
  o->center_object = f.Vector3("analysis_center_m");
  o->radius_m = f.Number("analysis_radius_m");
  if (!(o->radius_m > 0)) throw InputError(f.where(), "analysis_radius_m must be positive");
}

}  // namespace

nlohmann::json ToJson(const RecordCheck& r) {
  const LabelCheck& c = r.check;
  nlohmann::json j = {{"camera", r.camera},
                      {"index", r.index},
                      {"stamp_ns", r.stamp_ns},
                      {"object", r.object},
                      {"name", r.name},
                      {"instance", r.instance},
                      {"mode", r.mode},
                      {"verdict", ToString(c.verdict)},
                      {"reason_code", ToString(c.reason_code)},
                      {"reason", c.reason},
                      {"scene_points", c.scene_points},
                      {"occluder_pixels", c.occluder_pixels},
                      {"label_rvec", Vec(r.T_camera_object_label.rvec())},
                      {"label_t_m", Vec(r.T_camera_object_label.translation())}};
  if (r.depth_offset_ns != 0) {  // depth taken apart from colour: the label moved to the depth's exposure, or not
    j["depth_offset_ns"] = r.depth_offset_ns;
    j["label_shift_ns"] = r.label_shift_ns;
  }
  j["estimated"] = c.estimated;
  if (c.estimated) {
    j["segicp_rvec"] = Vec(c.T_camera_object_segicp.rvec());
    j["segicp_t_m"] = Vec(c.T_camera_object_segicp.translation());
    j["segicp_score"] = c.segicp_score;
    j["segicp_reliable"] = c.segicp_reliable;
    j["position_error_mm"] = c.errors.position_mm;
    j["rotation_axis_error_deg"] = c.errors.rotation_axis_deg;
    j["rotation_angle_error_deg"] = c.errors.rotation_angle_deg;
    j["success"] = c.success;
    j["icp_iterations"] = c.icp.iterations;
    j["icp_inlier_rmse_m"] = c.icp.inlier_rmse_m;
    if (c.observability.analysed) {
      j["observable_directions"] = c.observability.observable;
      const auto& info = c.observability.information;
      j["direction_information"] = std::vector<double>(info.data(), info.data() + info.size());
      j["direction_probe_loss"] = c.observability.probe_loss;
      j["unobservable"] = c.observability.unobservable;
      j["observed_position_error_mm"] = c.observed.position_mm;
      j["observed_rotation_error_deg"] = c.observed.rotation_deg;
      j["judged_where_observable"] = c.judged_where_observable();
      j["residual_rms_mm"] = 1e3 * c.observability.residual_rms_m;
      j["supported_points"] = c.observability.supported_points;
      if (c.observability.observable < 6) WriteJudgedDirections(c.observability, j);
    }
    if (!c.outline.empty()) {
      nlohmann::json steps = nlohmann::json::array();
      for (const OutlineStep& step : c.outline) {
        steps.push_back({{"direction", step.direction}, {"shift_mm", 1e3 * step.shift_m}, {"rise", step.rise},
                         {"judged", step.judged}});
        if (step.across_ray) steps.back()["across_ray"] = true;
      }
      j["outline"] = steps;
    }
    if (c.range_push_mm != 0) j["range_push_mm"] = c.range_push_mm;  // a range-biased object's fitted push
    j["precision_position_mm"] = c.precision.position_mm;
    j["precision_rotation_deg"] = c.precision.rotation_deg;
    j["accept_position_mm"] = c.accept_position_mm;
    j["accept_rotation_deg"] = c.accept_rotation_deg;
    j["resolution_position_mm"] = c.resolution_position_mm;
    j["resolution_rotation_deg"] = c.resolution_rotation_deg;
  }
  j["label_score"] = c.label_score;
  if (r.segmentation)
    j["segmentation"] = {{"iou", r.segmentation->iou}, {"precision", r.segmentation->precision},
                         {"recall", r.segmentation->recall}};
  return j;
}

RecordCheck RecordCheckFromJson(const nlohmann::json& j, const std::string& where) {
  const JsonFields f(j, where);
  RecordCheck r;
  r.camera = f.String("camera"), r.index = f.Integer("index"), r.stamp_ns = f.Integer("stamp_ns");
  r.object = static_cast<int>(f.Integer("object")), r.name = f.String("name");
  r.instance = static_cast<int>(f.Integer("instance")), r.mode = f.String("mode");
  r.T_camera_object_label = Rigid3d::FromRvec(f.Vector3("label_rvec"), f.Vector3("label_t_m"));
  if (f.Has("depth_offset_ns")) r.depth_offset_ns = f.Integer("depth_offset_ns"), r.label_shift_ns = f.Integer("label_shift_ns");
  LabelCheck& c = r.check;
  c.verdict = ParseEnum<Verdict>(f, "verdict", Verdict::kReject);
  c.reason_code = ParseEnum<VerdictReason>(f, "reason_code", VerdictReason::kObjectMountOff);
  c.reason = f.String("reason");
  c.scene_points = static_cast<int>(f.Integer("scene_points"));
  if (f.Has("occluder_pixels")) c.occluder_pixels = f.Integer("occluder_pixels");  // written since the depth cut
  c.estimated = f.Bool("estimated");
  if (c.estimated) {
    c.T_camera_object_segicp = Rigid3d::FromRvec(f.Vector3("segicp_rvec"), f.Vector3("segicp_t_m"));
    c.segicp_score = f.Number("segicp_score"), c.segicp_reliable = f.Bool("segicp_reliable");
    c.errors = {f.Number("position_error_mm"), f.Number("rotation_axis_error_deg"), f.Number("rotation_angle_error_deg")};
    c.success = f.Bool("success");
    c.icp.iterations = static_cast<int>(f.Integer("icp_iterations"));
    c.icp.inlier_rmse_m = f.Number("icp_inlier_rmse_m");
    if (f.Has("observable_directions")) {
      c.observability.analysed = true;
      c.observability.observable = static_cast<int>(f.Integer("observable_directions"));
      c.observability.unobservable = f.Strings("unobservable");
      c.observed = {f.Number("observed_position_error_mm"), f.Number("observed_rotation_error_deg")};
      if (c.observability.observable < 6 && f.Has("judged_directions")) ReadJudgedDirections(f, &c.observability);
    }
    if (f.Has("accept_position_mm")) {  // written since the bounds are per record
      c.precision = {f.Number("precision_position_mm"), f.Number("precision_rotation_deg")};
      c.accept_position_mm = f.Number("accept_position_mm"), c.accept_rotation_deg = f.Number("accept_rotation_deg");
    }
    if (f.Has("outline")) {  // written since the outline estimate
      const nlohmann::json& steps = f["outline"];
      if (!steps.is_array()) throw InputError(where, "outline: expected an array");
      for (size_t i = 0; i < steps.size(); ++i) {
        const JsonFields g(steps[i], Str(where, " outline[", i, "]"));
        c.outline.push_back({static_cast<int>(g.Integer("direction")), g.Has("across_ray") && g.Bool("across_ray"),
                             1e-3 * g.Number("shift_mm"), g.Number("rise"), g.Bool("judged")});
      }
    }
    if (f.Has("range_push_mm")) c.range_push_mm = f.Number("range_push_mm");  // only for a range-biased object
    if (f.Has("resolution_position_mm"))  // written since the floor takes the depth's resolution
      c.resolution_position_mm = f.Number("resolution_position_mm"),
      c.resolution_rotation_deg = f.Number("resolution_rotation_deg");
  }
  c.label_score = f.Number("label_score");
  if (f.Has("segmentation")) {
    const JsonFields g(f["segmentation"], where + " segmentation");
    r.segmentation = SegmentationScore{g.Number("iou"), g.Number("precision"), g.Number("recall")};
  }
  return r;
}

nlohmann::json ValidationSummaryJson(const ValidationSummary& s, const SessionCheckOptions& options,
                                     const fs::path& session_dir) {
  nlohmann::json j = {{"complete", true},
                      {"session", fs::absolute(session_dir).string()},
                      {"labels", fs::absolute(options.labels_dir).string()},
                      {"masks", options.masks_dir.empty() ? nlohmann::json() : nlohmann::json(fs::absolute(options.masks_dir).string())},
                      {"mask_values", options.masks_dir.empty() ? "label_instance" : ToString(options.mask_values)},
                      {"crops", options.crops == CropBackend::kRenderer ? "renderer" : "surface"},
                      {"mode", options.track ? "track" : "frame"},
                      {"frame_stride", options.frame_stride},
                      {"records", s.records},
                      {"records_without_pose", s.records_without_pose},
                      {"records_checked", s.records_checked},
                      {"segicp_success_rate", s.segicp_success_rate},
                      {"verdicts", s.verdicts},
                      {"reasons", s.reasons},
                      {"position_error_mm", StatJson(s.position_error_mm)},
                      {"rotation_axis_error_deg", StatJson(s.rotation_axis_error_deg)},
                      {"rotation_angle_error_deg", StatJson(s.rotation_angle_error_deg)},
                      {"label_score", StatJson(s.label_score)},
                      {"seconds", s.seconds}};
  for (const char* v : {"accept", "suspect", "reject"})
    if (!j["verdicts"].contains(v)) j["verdicts"][v] = 0;
  if (!s.nothing_checked_why.empty()) j["nothing_checked_why"] = s.nothing_checked_why;
  if (s.labels_moved_to_depth_time + s.labels_not_movable_to_depth_time > 0) {
    j["labels_moved_to_depth_time"] = s.labels_moved_to_depth_time;
    j["labels_not_movable_to_depth_time"] = s.labels_not_movable_to_depth_time;
  }
  if (s.session_wide)
    j["session_wide"] = {{"ran", s.session_wide->ran}, {"why_not", s.session_wide->why_not},
                         {"findings", s.session_wide->findings}, {"records_flagged", s.session_wide->records_flagged}};
  if (s.has_segmentation)
    j["segmentation"] = {{"iou", StatJson(s.iou)}, {"precision", StatJson(s.precision)}, {"recall", StatJson(s.recall)}};
  return j;
}

void WriteValidationRun(const SessionValidation& validation, const SessionCheckOptions& options,
                        const fs::path& session_dir, const fs::path& dir, const fs::path& report_dir) {
  const ValidationRunLayout layout{dir};
  std::string jsonl;
  for (const RecordCheck& r : validation.records) jsonl += ToJson(r).dump() + "\n";
  WriteTextAtomically(layout.records_jsonl(), jsonl);
  WriteTextAtomically(layout.report_html(), ValidationReportHtml(validation, options.validate.verdict, report_dir));
  // The summary last: its presence marks a whole output.
  WriteTextAtomically(layout.summary_json(), ValidationSummaryJson(validation.summary, options, session_dir).dump(2) + "\n");
}

LabelRunView LabelRunViewOf(const LabelRun& run, int64_t frame_begin, int64_t frame_end) {
  LabelRunView view;
  for (const LabelRecord& r : run.records) {
    if (r.index < frame_begin || (frame_end >= 0 && r.index >= frame_end)) continue;
    ++view.total;
    if (!r.has_pose) continue;  // a label without a pose has nothing to check
    RecordCheck c;
    c.camera = r.camera, c.index = r.index, c.stamp_ns = r.stamp_ns, c.object = r.object, c.name = r.name;
    c.instance = r.instance;
    c.T_camera_object_label = r.T_camera_mesh();
    view.records.push_back(std::move(c));
  }
  const LabelRunLayout layout = run.layout;
  view.instance_png = [layout](const std::string& camera, int64_t index) { return layout.InstancePng(camera, index); };
  view.overlay_png = [layout](const std::string& camera, int64_t index) { return layout.OverlayPng(camera, index); };
  return view;
}

ValidationRun ValidationRun::Read(const fs::path& dir) {
  ValidationRun run;
  run.layout.dir = dir;
  if (!fs::exists(run.layout.summary_json()))
    throw InputError(dir.string(), "is not a finished validation run (no validation.json)");
  run.summary = ReadJsonFile(run.layout.summary_json());
  for (const auto& [where, j] : ReadJsonLines(run.layout.records_jsonl())) run.records.push_back(RecordCheckFromJson(j, where));
  return run;
}

}  // namespace mocap::pipeline
