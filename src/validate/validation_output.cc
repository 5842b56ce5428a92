#include "validate/validation_output.h"

#include <fstream>

#include "core/check.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json StatJson(const Stat& s) {
  return {{"count", s.count}, {"median", s.median}, {"p95", s.p95}, {"std", s.std}, {"max", s.max}};
}

void WriteText(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  out.close();
  if (!out) throw InputError(file.string(), "could not write (disk full or not writable?)");
}

std::string_view ToString(MaskValues values) { return values == MaskValues::kObjectId ? "object" : "instance"; }

}  // namespace

nlohmann::json ValidationRecordJson(const RecordCheck& r) {
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
                      {"label_rvec", Vec(r.T_camera_object_label.rvec())},
                      {"label_t_m", Vec(r.T_camera_object_label.translation())}};
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
  }
  j["label_score"] = c.label_score;
  if (r.segmentation)
    j["segmentation"] = {{"iou", r.segmentation->iou}, {"precision", r.segmentation->precision},
                         {"recall", r.segmentation->recall}};
  return j;
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
  if (s.has_segmentation)
    j["segmentation"] = {{"iou", StatJson(s.iou)}, {"precision", StatJson(s.precision)}, {"recall", StatJson(s.recall)}};
  return j;
}

void WriteValidation(const SessionValidation& validation, const SessionCheckOptions& options,
                     const fs::path& session_dir, const fs::path& out_dir) {
  if (fs::exists(out_dir) && !fs::is_empty(out_dir) && !fs::exists(out_dir / "validation.json"))
    throw InputError(out_dir.string(), "exists and is not an earlier validation output; choose another --out");
  fs::path partial = out_dir;
  partial += ".partial";
  fs::remove_all(partial);
  fs::create_directories(partial);
  std::string jsonl;
  for (const RecordCheck& r : validation.records) jsonl += ValidationRecordJson(r).dump() + "\n";
  WriteText(partial / "validation.jsonl", jsonl);
  WriteText(partial / "report.html", ValidationReportHtml(validation, options.validate.verdict, out_dir));
  // The summary last: its presence marks a whole output.
  WriteText(partial / "validation.json", ValidationSummaryJson(validation.summary, options, session_dir).dump(2) + "\n");
  fs::remove_all(out_dir);
  fs::rename(partial, out_dir);
}

SessionValidation ValidateSession(const SessionReader& session, const std::vector<ValidationObject>& objects,
                                  const SessionCheckOptions& options, const fs::path& out_dir) {
  SessionValidation validation = CheckSession(session, objects, options);
  if (!out_dir.empty()) WriteValidation(validation, options, session.dir(), out_dir);
  return validation;
}

}  // namespace mocap
