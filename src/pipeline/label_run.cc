#include "pipeline/label_run.h"

#include <fstream>

#include "core/check.h"
#include "label/label_png.h"
#include "pipeline/json_read.h"
#include "pipeline/yaml_write.h"
#include "session/records.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json Array3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// A view of `image` (no copy: the encoder only reads it).
cv::Mat ToMat(const LabelImage& image) {
  return cv::Mat(image.height, image.width, CV_16UC1, const_cast<uint16_t*>(image.data.data()));
}

void AddPoseFields(json& j, const LabelRecord& r) {
  j["rvec"] = Array3(r.rvec);
  j["t_m"] = Array3(r.t_m);
  j["quat_wxyz"] = {r.quat_wxyz[0], r.quat_wxyz[1], r.quat_wxyz[2], r.quat_wxyz[3]};
  j["interp_gap_ms"] = r.interp_gap_ms;
  j["speed_m_s"] = r.speed_m_s ? json(*r.speed_m_s) : json();
  j["speed_deg_s"] = r.speed_deg_s ? json(*r.speed_deg_s) : json();
  j["bbox_obj"] = r.bbox_obj;
  j["bbox_visib"] = r.bbox_visib;
  j["px_count_all"] = r.px_count_all;
  j["px_count_valid"] = r.px_count_valid ? json(*r.px_count_valid) : json();
  j["px_count_visib"] = r.px_count_visib;
  j["px_count_visib_measured"] = r.px_count_visib_measured ? json(*r.px_count_visib_measured) : json();
  j["px_count_visib_assumed"] = r.px_count_visib_assumed ? json(*r.px_count_visib_assumed) : json();
  j["mask_confidence"] = r.mask_confidence ? json(*r.mask_confidence) : json();
  j["visib_fract"] = r.visib_fract;
  j["visib_fract_model"] = r.visib_fract_model;
  j["visib_source"] = r.visib_source;
  if (r.has_mask_fields) {
    j["mask_rect"] = r.mask_rect ? json(*r.mask_rect) : json();
    j["mask_row"] = r.mask_row ? json(*r.mask_row) : json();
  }
}

void ReadPoseFields(const JsonFields& f, LabelRecord& r) {
  r.has_pose = true;
  r.rvec = f.Vector3("rvec");
  r.t_m = f.Vector3("t_m");
  const std::vector<double> q = f.Numbers("quat_wxyz", 4);
  r.quat_wxyz = {q[0], q[1], q[2], q[3]};
  r.interp_gap_ms = f.Number("interp_gap_ms");
  r.speed_m_s = f.OptionalNumber("speed_m_s");
  r.speed_deg_s = f.OptionalNumber("speed_deg_s");
  r.bbox_obj = f.Box("bbox_obj");
  r.bbox_visib = f.Box("bbox_visib");
  r.px_count_all = f.Integer("px_count_all");
  if (f.Has("px_count_valid") && !f["px_count_valid"].is_null()) r.px_count_valid = f.Integer("px_count_valid");
  r.px_count_visib = f.Integer("px_count_visib");
  const auto optional_integer = [&](const char* key) -> std::optional<int64_t> {
    if (!f.Has(key) || f[key].is_null()) return std::nullopt;
    return f.Integer(key);
  };
  r.px_count_visib_measured = optional_integer("px_count_visib_measured");
  r.px_count_visib_assumed = optional_integer("px_count_visib_assumed");
  r.mask_confidence = f.OptionalNumber("mask_confidence");
  r.visib_fract = f.Number("visib_fract");
  r.visib_fract_model = f.Number("visib_fract_model");
  r.visib_source = f.String("visib_source");
  r.has_mask_fields = f.Has("mask_rect");
  if (r.has_mask_fields && !f["mask_rect"].is_null()) r.mask_rect = f.Box("mask_rect");
  if (f.Has("mask_row") && !f["mask_row"].is_null()) r.mask_row = static_cast<int>(f.Integer("mask_row"));
}

void WriteBopMasks(const LabelRunLayout& layout, const LabelledFrame& frame) {
  const int w = frame.render.instance_ids.width, h = frame.render.instance_ids.height;
  for (const InstanceResult& r : frame.results) {
    if (r.labels == nullptr) continue;
    const ObjectMasks& m = r.labels->masks;
    const int instance = r.instance->instance_id;
    WriteLabelPng(layout.BopMaskPng(frame.camera, "mask", frame.index, instance), FullMaskImage(m.amodal, m.rect, w, h));
    WriteLabelPng(layout.BopMaskPng(frame.camera, "mask_visib", frame.index, instance),
                  FullMaskImage(m.visible_model, m.rect, w, h));
    if (!m.visible_measured.empty())
      WriteLabelPng(layout.BopMaskPng(frame.camera, "mask_visib_depth", frame.index, instance),
                    FullMaskImage(m.visible_measured, m.rect, w, h));
  }
}

}  // namespace

json ToJson(const LabelRecord& r) {
  json j = {{"camera", r.camera}, {"frame", r.frame},   {"index", r.index}, {"stamp_ns", r.stamp_ns},
            {"object", r.object}, {"name", r.name},     {"class", r.object_class},
            {"instance", r.instance}, {"body", r.body}, {"flags", r.flags}};
  if (!r.source_id.empty()) j["source_id"] = r.source_id;
  if (!r.has_pose) {
    j["reason"] = r.reason;
    return j;
  }
  AddPoseFields(j, r);
  if (!r.reason.empty()) j["reason"] = r.reason;  // a posed record's doubt, e.g. its depth file unreadable
  return j;
}

LabelRecord LabelRecordFromJson(const json& j, const std::string& where) {
  const JsonFields f(j, where);
  LabelRecord r;
  r.camera = f.String("camera");
  r.frame = f.Integer("frame");
  r.index = f.Integer("index");
  r.stamp_ns = f.Integer("stamp_ns");
  r.source_id = f.Has("source_id") ? f.String("source_id") : "";
  r.object = static_cast<int>(f.Integer("object"));
  r.name = f.String("name");
  r.object_class = f.String("class");
  r.instance = static_cast<int>(f.Integer("instance"));
  if (r.instance <= 0 || r.instance > 65535) throw InputError(where, Str("instance id ", r.instance, " not in 1..65535"));
  r.body = f.String("body");
  r.flags = f.Strings("flags");
  if (f.Has("rvec")) ReadPoseFields(f, r);
  if (!f.Has("rvec") || f.Has("reason")) r.reason = f.String("reason");
  return r;
}

LabelRecord MakeLabelRecord(const LabelledFrame& frame, const InstanceResult& result) {
  const LabelInstance& inst = *result.instance;
  LabelRecord r;
  r.camera = frame.camera, r.frame = frame.record.frame, r.index = frame.index, r.stamp_ns = frame.record.stamp_ns;
  r.source_id = frame.record.source_id;
  r.object = inst.object->id, r.name = inst.object->name, r.object_class = inst.object->object_class;
  r.instance = inst.instance_id, r.body = inst.mount->body, r.flags = result.pose.flags;
  r.reason = result.pose.reason;
  if (!result.pose.T_camera_mesh) return r;
  const PoseFields pose = MakePoseFields(*result.pose.T_camera_mesh);
  r.has_pose = true;
  r.rvec = pose.rvec, r.t_m = pose.t_m;
  r.quat_wxyz = {pose.quat_wxyz[0], pose.quat_wxyz[1], pose.quat_wxyz[2], pose.quat_wxyz[3]};
  r.interp_gap_ms = result.pose.interp_gap_ms;
  if (result.pose.speed_m_per_s >= 0) r.speed_m_s = result.pose.speed_m_per_s;
  if (result.pose.speed_deg_per_s >= 0) r.speed_deg_s = result.pose.speed_deg_per_s;
  const ObjectStats& s = result.labels->stats;
  r.bbox_obj = s.bbox_obj, r.bbox_visib = s.bbox_visib;
  r.px_count_all = s.px_count_all, r.px_count_visib = s.px_count_visib;
  if (frame.has_measured_depth) r.px_count_valid = s.px_count_valid;
  if (frame.has_measured_depth && s.mask_confidence >= 0) {
    r.px_count_visib_measured = s.px_count_visib_measured, r.px_count_visib_assumed = s.px_count_visib_assumed;
    r.mask_confidence = s.mask_confidence;
  }
  r.visib_fract = s.visib_fract, r.visib_fract_model = s.visib_fract_model;
  r.visib_source = frame.has_measured_depth ? "measured_depth" : "model";
  if (result.packed != nullptr) {
    r.has_mask_fields = true;
    const PixelRect& m = result.packed->rect;
    if (!m.empty()) r.mask_rect = std::array<int, 4>{m.x, m.y, m.width, m.height}, r.mask_row = result.packed->file_row;
  }
  return r;
}

fs::path LabelRunLayout::FramePng(const std::string& camera, const std::string& kind, int64_t index) const {
  return dir / camera / kind / (FrameFileStem(index) + ".png");
}

fs::path LabelRunLayout::DepthExr(const std::string& camera, int64_t index) const {
  return dir / camera / "depth" / (FrameFileStem(index) + ".exr");
}

fs::path LabelRunLayout::BopMaskPng(const std::string& camera, const std::string& kind, int64_t index, int instance) const {
  return dir / camera / kind / (FrameFileStem(index) + "_" + FrameFileStem(instance) + ".png");
}

std::vector<std::string> LabelRunLayout::FrameFolders(const FrameOutputOptions& output) {
  std::vector<std::string> folders = {"instance", "class"};
  if (output.write_depth) folders.push_back("depth");
  if (output.write_masks) folders.push_back("mask_bits");
  if (output.write_bop_masks) folders.insert(folders.end(), {"mask", "mask_visib", "mask_visib_depth"});
  if (output.write_overlay) folders.push_back("overlay");
  return folders;
}

void LabelRunWriter::Begin(const std::vector<std::string>& cameras, const FrameOutputOptions& output) {
  cameras_ = cameras;
  output_ = output;
  for (const std::string& camera : cameras)
    for (const std::string& folder : LabelRunLayout::FrameFolders(output)) fs::create_directories(layout_.dir / camera / folder);
}

void LabelRunWriter::Write(const LabelledFrame& frame) {
  WriteLabelPng(layout_.InstancePng(frame.camera, frame.index), ToMat(frame.render.instance_ids));
  WriteLabelPng(layout_.ClassPng(frame.camera, frame.index), ToMat(ClassImage(frame.render, frame.results)));
  if (output_.write_depth)
    WriteRenderedDepthExr(layout_.DepthExr(frame.camera, frame.index), frame.render.depth_m, output_.depth_compression);
  if (!frame.frame_masks.empty()) WriteLabelPng(layout_.MaskBitsPng(frame.camera, frame.index), frame.frame_masks);
  if (output_.write_bop_masks) WriteBopMasks(layout_, frame);
  if (output_.write_overlay && !frame.color.empty())
    WriteLabelPng(layout_.OverlayPng(frame.camera, frame.index), OverlayImage(frame.color, frame.render, frame.results));
  std::string lines;
  for (const InstanceResult& r : frame.results) lines += ToJson(MakeLabelRecord(frame, r)).dump() + '\n';
  const auto camera = static_cast<size_t>(std::find(cameras_.begin(), cameras_.end(), frame.camera) - cameras_.begin());
  std::lock_guard lock(mutex_);
  lines_[{camera, frame.index}] = std::move(lines);
}

void LabelRunWriter::Finish(const json& manifest) {
  std::string text;
  for (const auto& [key, lines] : lines_) text += lines;
  WriteTextAtomically(layout_.labels_jsonl(), text);
  // The manifest last: its presence marks a finished run.
  WriteTextAtomically(layout_.manifest_json(), manifest.dump(2) + "\n");
}

LabelRun LabelRun::Read(const fs::path& dir) {
  LabelRun run;
  run.layout.dir = dir;
  if (!fs::exists(run.layout.manifest_json()))
    throw InputError(dir.string(), "is not a finished label run (no label_manifest.json); pass the folder `mocaplabel label --out` wrote");
  run.manifest = ReadJsonFile(run.layout.manifest_json());
  for (const auto& [where, j] : ReadJsonLines(run.layout.labels_jsonl())) run.records.push_back(LabelRecordFromJson(j, where));
  return run;
}

}  // namespace mocap::pipeline
