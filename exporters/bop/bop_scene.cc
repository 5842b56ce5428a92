// One frame of a BOP scene folder: rgb/, depth/, mask/, mask_visib/ and its entries of scene_camera.json,
// scene_gt.json and scene_gt_info.json (formats.md §1; bop_toolkit_lib/inout.py save_scene_camera,
// save_scene_gt; calc_gt_info.py for the statistics).
#include <cmath>
#include <opencv2/core.hpp>

#include "core/check.h"
#include "core/text.h"
#include "exporters/bop/bop_internal.h"
#include "label/label_output.h"
#include "label/label_png.h"
#include "session/durable_file.h"
#include "session/png_write.h"

namespace mocap::exporters::bop {
namespace fs = std::filesystem;
namespace {

std::string Padded(int64_t value) {
  char text[32];
  std::snprintf(text, sizeof text, "%06lld", static_cast<long long>(value));
  return text;
}

std::vector<double> RowMajor(const Eigen::Matrix3d& R) {
  return {R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)};
}

std::vector<double> Millimetres(const Eigen::Vector3d& t_m) { return {t_m.x() * 1e3, t_m.y() * 1e3, t_m.z() * 1e3}; }

/// The frame's depth as BOP wants it; returns depth_scale (mm per unit), or 0 when none was written.
/// Registered 16-bit PNGs are linked as recorded (no re-encode); others go through ColorAlignedDepthM.
double WriteDepth(const ExportScene& scene, const ExportFrame& frame, const fs::path& file, const BopOptions& o) {
  if (frame.depth_path.empty() || !o.write_depth) return 0;
  if (scene.depth_registered_to_color && LowerExtension(frame.depth_path) == ".png") {
    LinkOrCopyFile(frame.depth_path, file);
    return scene.depth_unit_m * 1e3;
  }
  const cv::Mat depth_m = ColorAlignedDepthM(scene, frame);
  cv::Mat units(depth_m.rows, depth_m.cols, CV_16UC1);
  const double per_m = 1e3 / o.converted_depth_scale_mm;
  for (int v = 0; v < depth_m.rows; ++v)
    for (int u = 0; u < depth_m.cols; ++u) {
      const double value = std::round(depth_m.at<float>(v, u) * per_m);
      units.at<uint16_t>(v, u) = value > 0 && value <= 65535 ? static_cast<uint16_t>(value) : 0;  // out of range: no depth
    }
  WriteFileBytes(file, EncodeGray16Png(units));
  return o.converted_depth_scale_mm;
}

nlohmann::json CameraEntry(const ExportScene& scene, const ExportFrame& frame, double depth_scale) {
  const PinholeCamera& c = scene.color_camera;
  nlohmann::json entry = {{"cam_K", {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0}}};
  if (depth_scale > 0) entry["depth_scale"] = depth_scale;
  if (frame.T_tracker_camera) {  // BOP's world is the tracker's frame: w2c maps it into the camera
    const Rigid3d T_camera_tracker = frame.T_tracker_camera->inverse();
    entry["cam_R_w2c"] = RowMajor(T_camera_tracker.rotation_matrix());
    entry["cam_t_w2c"] = Millimetres(T_camera_tracker.translation());
  }
  return entry;
}

nlohmann::json GtInfo(const pipeline::LabelRecord& r) {
  return {{"bbox_obj", r.bbox_obj},          {"bbox_visib", r.bbox_visib},
          {"px_count_all", r.px_count_all},  {"px_count_valid", r.px_count_valid.value_or(0)},
          {"px_count_visib", r.px_count_visib}, {"visib_fract", r.visib_fract}};
}

/// mask/ and mask_visib/ of one gt instance: full-image 0/255 PNGs (all zero when it covers no pixel).
void WriteMasks(const ExportScene& scene, const fs::path& scene_dir, const std::string& name, const ObjectMasks& masks,
                const pipeline::LabelRecord& record) {
  const int width = scene.color_camera.width, height = scene.color_camera.height;
  const cv::Mat amodal = masks.rect.empty() ? cv::Mat::zeros(height, width, CV_8UC1)
                                            : FullMaskImage(masks.amodal, masks.rect, width, height);
  const cv::Mat visible = masks.rect.empty() ? cv::Mat::zeros(height, width, CV_8UC1)
                                             : FullMaskImage(VisibleMask(masks, record), masks.rect, width, height);
  WriteLabelPng(scene_dir / "mask" / name, amodal);
  WriteLabelPng(scene_dir / "mask_visib" / name, visible);
}

}  // namespace

int64_t WriteBopFrame(const Dataset& dataset, const ExportFrame& frame, const fs::path& scene_dir,
                      const BopOptions& options, SceneJson& json) {
  const ExportScene& scene = dataset.scene_of(frame);
  const std::string im = Padded(frame.im_id);
  int64_t files = 0;
  if (!frame.color_path.empty()) {
    LinkOrCopyFile(frame.color_path, scene_dir / "rgb" / (im + LowerExtension(frame.color_path)));
    ++files;
  }
  const double depth_scale = WriteDepth(scene, frame, scene_dir / "depth" / (im + ".png"), options);
  files += depth_scale > 0 ? 1 : 0;
  const std::vector<ObjectMasks> masks = options.write_masks ? ReadFrameMasks(scene, frame) : std::vector<ObjectMasks>{};
  nlohmann::json gt = nlohmann::json::array(), gt_info = nlohmann::json::array();
  for (size_t i = 0; i < frame.instances.size(); ++i) {
    const pipeline::LabelRecord& r = frame.instances[i].record;
    if (!r.has_pose) continue;  // BOP's gt is poses: a label without one has nothing to say
    const Rigid3d T_camera_mesh = r.T_camera_mesh();
    gt.push_back({{"cam_R_m2c", RowMajor(T_camera_mesh.rotation_matrix())},
                  {"cam_t_m2c", Millimetres(T_camera_mesh.translation())},
                  {"obj_id", r.object}});
    gt_info.push_back(GtInfo(r));
    if (options.write_masks) {
      WriteMasks(scene, scene_dir, im + "_" + Padded(static_cast<int64_t>(gt.size()) - 1) + ".png", masks[i], r);
      files += 2;
    }
  }
  const std::lock_guard lock(json.mutex);
  json.camera[frame.im_id] = CameraEntry(scene, frame, depth_scale);
  json.gt[frame.im_id] = std::move(gt);
  json.gt_info[frame.im_id] = std::move(gt_info);
  return files;
}

}  // namespace mocap::exporters::bop
