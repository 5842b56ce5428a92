#pragma once
// The files of a label run (docs/labels.md): per camera and frame the instance and class PNGs (uint16),
// the rendered depth (OpenEXR, metres), one mask PNG per frame carrying every object's three masks
// (mask_file.h), optionally BOP-style full-size masks and an overlay, and one labels.jsonl record per
// frame and object instance.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "label/depth_exr.h"
#include "label/mask_file.h"
#include "label/object_labels.h"
#include "label/pose_chain.h"
#include "session/records.h"

namespace mocap {

struct FrameOutputOptions {
  bool write_depth = true;    ///< rendered depth as OpenEXR
  DepthCompression depth_compression = DepthCompression::kRle;  ///< lossless; RLE is the cheapest that shrinks
  bool write_masks = true;    ///< one packed mask PNG per object (amodal, visible by model, by measured depth)
  bool write_bop_masks = false;  ///< also three full-size 0/255 mask PNGs per object, laid out as BOP's
  bool write_overlay = false; ///< label colours over the RGB image
};

/// What was computed for one instance in one frame.
struct InstanceResult {
  const LabelInstance* instance = nullptr;
  InstancePose pose;
  const ObjectLabels* labels = nullptr;  ///< null when there was no pose to render
  /// The packed masks written for this instance; null when masks are not written (no `mask_rect`).
  const PackedMasks* packed = nullptr;
};

/// "000123": the file stem of camera record `index`.
std::string FrameStem(int64_t index);

/// Writes a frame's images under out_dir/<camera>/. `color` may be empty (no overlay then);
/// `frame_masks` is StackMasks of the results' packed masks (empty: no mask file).
void WriteFrameImages(const std::filesystem::path& out_dir, const std::string& camera, int64_t index,
                      const RenderOutput& render, const std::vector<InstanceResult>& results, const cv::Mat& color,
                      const cv::Mat& frame_masks, const FrameOutputOptions& options);

/// The labels.jsonl record of one instance in one frame (field meanings in docs/labels.md).
nlohmann::json LabelRecord(const std::string& camera, int64_t index, const CameraFrameRecord& frame,
                           const InstanceResult& result, bool has_measured_depth);

}  // namespace mocap
