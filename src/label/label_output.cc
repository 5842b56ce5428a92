#include "label/label_output.h"

#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/check.h"

namespace mocap {
namespace {

/// A view of `image` (no copy: the encoder only reads it).
cv::Mat ToMat(const LabelImage& image) {
  return cv::Mat(image.height, image.width, CV_16UC1, const_cast<uint16_t*>(image.data.data()));
}

/// Object ids per pixel, through a lookup from instance id, into a buffer of the calling thread that the
/// next call overwrites (no fresh pages to fault in per frame). Only the objects' rectangles are looked
/// up: no instance id lies outside them.
const LabelImage& ClassImage(const RenderOutput& render, const std::vector<InstanceResult>& results) {
  std::vector<uint16_t> class_of(1, 0);
  for (const InstanceResult& r : results) {
    const uint16_t id = r.instance->instance_id;
    if (class_of.size() <= id) class_of.resize(id + 1u, 0);
    class_of[id] = static_cast<uint16_t>(r.instance->object->id);
  }
  const LabelImage& ids = render.instance_ids;
  thread_local LabelImage classes;
  classes.width = ids.width, classes.height = ids.height;
  classes.data.assign(ids.data.size(), 0);
  for (const ObjectLayer& layer : render.layers) {
    const PixelRect& r = layer.rect;
    for (int v = r.y; v < r.y + r.height; ++v)
      for (int u = r.x; u < r.x + r.width; ++u) {
        const uint16_t id = ids.at(u, v);
        classes.at(u, v) = id < class_of.size() ? class_of[id] : 0;
      }
  }
  return classes;
}

cv::Mat MaskMat(const std::vector<uint8_t>& mask, const PixelRect& rect, int width, int height) {
  const Image<uint8_t> full = ToFullImage(mask, rect, width, height);
  return cv::Mat(height, width, CV_8UC1, const_cast<uint8_t*>(full.data.data())).clone();
}

void WriteBopMasks(const std::filesystem::path& dir, const std::string& stem, const RenderOutput& render,
                   const std::vector<InstanceResult>& results) {
  const int w = render.instance_ids.width, h = render.instance_ids.height;
  for (const InstanceResult& r : results) {
    if (r.labels == nullptr) continue;
    const ObjectMasks& m = r.labels->masks;
    const std::string name = stem + "_" + FrameStem(r.instance->instance_id) + ".png";
    WriteLabelPng(dir / "mask" / name, MaskMat(m.amodal, m.rect, w, h));
    WriteLabelPng(dir / "mask_visib" / name, MaskMat(m.visible_model, m.rect, w, h));
    if (!m.visible_measured.empty())
      WriteLabelPng(dir / "mask_visib_depth" / name, MaskMat(m.visible_measured, m.rect, w, h));
  }
}

cv::Scalar Colour(uint16_t instance_id) {
  // Well-separated hues by the golden angle, full saturation (BGR).
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar((instance_id * 137) % 180, 220, 255)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return {static_cast<double>(c[0]), static_cast<double>(c[1]), static_cast<double>(c[2])};
}

cv::Mat Overlay(const cv::Mat& color, const RenderOutput& render, const std::vector<InstanceResult>& results) {
  cv::Mat out = color.clone();
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols; ++u) {
      const uint16_t id = render.instance_ids.at(u, v);
      if (id == 0) continue;
      const cv::Scalar c = Colour(id);
      cv::Vec3b& px = out.at<cv::Vec3b>(v, u);
      for (int k = 0; k < 3; ++k) px[k] = static_cast<uint8_t>(0.45 * px[k] + 0.55 * c[k]);
    }
  }
  for (const InstanceResult& r : results) {
    if (r.labels == nullptr || r.labels->stats.bbox_visib[0] < 0) continue;
    const auto& b = r.labels->stats.bbox_visib;
    const cv::Scalar c = Colour(r.instance->instance_id);
    cv::rectangle(out, cv::Rect(b[0], b[1], b[2] + 1, b[3] + 1), c, 1);
    cv::putText(out, r.instance->object->name, {b[0], std::max(b[1] - 3, 10)}, cv::FONT_HERSHEY_SIMPLEX, 0.4, c, 1);
  }
  return out;
}

}  // namespace

std::string FrameStem(int64_t index) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%06lld", static_cast<long long>(index));
  return buffer;
}

void WriteFrameImages(const std::filesystem::path& out_dir, const std::string& camera, int64_t index,
                      const RenderOutput& render, const std::vector<InstanceResult>& results, const cv::Mat& color,
                      const cv::Mat& frame_masks, const FrameOutputOptions& options) {
  const std::filesystem::path dir = out_dir / camera;
  const std::string stem = FrameStem(index);
  WriteLabelPng(dir / "instance" / (stem + ".png"), ToMat(render.instance_ids));
  const LabelImage& classes = ClassImage(render, results);
  WriteLabelPng(dir / "class" / (stem + ".png"), ToMat(classes));
  if (options.write_depth) WriteRenderedDepthExr(dir / "depth" / (stem + ".exr"), render.depth_m, options.depth_compression);
  if (!frame_masks.empty()) WriteLabelPng(dir / "mask_bits" / (stem + ".png"), frame_masks);
  if (options.write_bop_masks) WriteBopMasks(dir, stem, render, results);
  if (options.write_overlay && !color.empty())
    WriteLabelPng(dir / "overlay" / (stem + ".png"), Overlay(color, render, results));
}

nlohmann::json LabelRecord(const std::string& camera, int64_t index, const CameraFrameRecord& frame,
                           const InstanceResult& result, bool has_measured_depth) {
  const LabelInstance& inst = *result.instance;
  nlohmann::json j = {{"camera", camera},
                      {"frame", frame.frame},
                      {"index", index},
                      {"stamp_ns", frame.stamp_ns},
                      {"object", inst.object->id},
                      {"name", inst.object->name},
                      {"class", inst.object->object_class},
                      {"instance", inst.instance_id},
                      {"body", inst.mount->body},
                      {"flags", result.pose.flags}};
  if (!frame.source_id.empty()) j["source_id"] = frame.source_id;
  if (!result.pose.T_camera_mesh) {
    j["reason"] = result.pose.reason;
    return j;
  }
  const PoseFields pose = MakePoseFields(*result.pose.T_camera_mesh);
  j["rvec"] = {pose.rvec.x(), pose.rvec.y(), pose.rvec.z()};
  j["t_m"] = {pose.t_m.x(), pose.t_m.y(), pose.t_m.z()};
  j["quat_wxyz"] = {pose.quat_wxyz[0], pose.quat_wxyz[1], pose.quat_wxyz[2], pose.quat_wxyz[3]};
  j["interp_gap_ms"] = result.pose.interp_gap_ms;
  j["speed_m_s"] = result.pose.speed_m_per_s >= 0 ? nlohmann::json(result.pose.speed_m_per_s) : nlohmann::json();
  j["speed_deg_s"] = result.pose.speed_deg_per_s >= 0 ? nlohmann::json(result.pose.speed_deg_per_s) : nlohmann::json();
  const ObjectStats& s = result.labels->stats;
  j["bbox_obj"] = s.bbox_obj;
  j["bbox_visib"] = s.bbox_visib;
  j["px_count_all"] = s.px_count_all;
  j["px_count_valid"] = has_measured_depth ? nlohmann::json(s.px_count_valid) : nlohmann::json();
  j["px_count_visib"] = s.px_count_visib;
  j["visib_fract"] = s.visib_fract;
  j["visib_fract_model"] = s.visib_fract_model;
  j["visib_source"] = has_measured_depth ? "measured_depth" : "model";
  if (result.packed != nullptr) {
    const PixelRect& m = result.packed->rect;
    j["mask_rect"] = m.empty() ? nlohmann::json() : nlohmann::json{m.x, m.y, m.width, m.height};
    j["mask_row"] = m.empty() ? nlohmann::json() : nlohmann::json(result.packed->file_row);
  }
  return j;
}

}  // namespace mocap
