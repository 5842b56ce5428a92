#pragma once
// The files of a label run (docs/labels.md): per camera and frame the instance and class PNGs (uint16),
// the rendered depth (OpenEXR, metres), three masks per object, an optional overlay, and one
// labels.jsonl record per frame and object instance.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "label/object_labels.h"
#include "label/pose_chain.h"
#include "session/records.h"

namespace mocap {

struct FrameOutputOptions {
  bool write_depth = true;    ///< rendered depth as OpenEXR
  bool write_masks = true;    ///< per-object mask PNGs (amodal, visible by model, visible by measured depth)
  bool write_overlay = false; ///< label colours over the RGB image
};

/// What was computed for one instance in one frame.
struct InstanceResult {
  const LabelInstance* instance = nullptr;
  InstancePose pose;
  const ObjectLabels* labels = nullptr;  ///< null when there was no pose to render
};

/// "000123": the file stem of camera record `index`.
std::string FrameStem(int64_t index);

/// Writes a frame's images under out_dir/<camera>/. `color` may be empty (no overlay then).
void WriteFrameImages(const std::filesystem::path& out_dir, const std::string& camera, int64_t index,
                      const RenderOutput& render, const std::vector<InstanceResult>& results, const cv::Mat& color,
                      const FrameOutputOptions& options);

/// The labels.jsonl record of one instance in one frame (field meanings in docs/labels.md).
nlohmann::json LabelRecord(const std::string& camera, int64_t index, const CameraFrameRecord& frame,
                           const InstanceResult& result, bool has_measured_depth);

}  // namespace mocap
