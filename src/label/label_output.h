#pragma once
// What the labeller hands on for each frame (LabelledFrame, to a LabelSink) and the images derived from
// it: the class image, the overlay, BOP's full-size masks. The files of a label run and their layout are
// the pipeline's (pipeline/label_run.h, docs/labels.md).
#include <filesystem>
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

/// Object ids per pixel (the class image), from the render's instance ids through each instance's
/// object id. Returns a buffer of the calling thread that the next call overwrites.
const LabelImage& ClassImage(const RenderOutput& render, const std::vector<InstanceResult>& results);

/// Label colours over the RGB image, with each visible box and the object's name.
cv::Mat OverlayImage(const cv::Mat& color, const RenderOutput& render, const std::vector<InstanceResult>& results);

/// A full-size 0/255 mask (BOP's mask files) of a mask cropped to `rect`.
cv::Mat FullMaskImage(const std::vector<uint8_t>& mask, const PixelRect& rect, int width, int height);

/// One labelled camera frame, handed to a LabelSink: the render, each instance's pose, flags, labels
/// and packed masks, the colour image (only when an overlay is asked for) and the frame's mask image
/// (StackMasks of the packed masks; empty when none).
struct LabelledFrame {
  const std::string& camera;
  int64_t index = 0;  ///< camera record index
  const CameraFrameRecord& record;
  const RenderOutput& render;
  const std::vector<InstanceResult>& results;
  const cv::Mat& color;
  const cv::Mat& frame_masks;
  bool has_measured_depth = false;
};

/// Where labelled frames go (pipeline/label_run.h writes them as a label run). The labeller itself knows
/// no file layout.
class LabelSink {
 public:
  virtual ~LabelSink() = default;
  /// Called once before any frame, with the cameras that will be labelled.
  virtual void Begin(const std::vector<std::string>& cameras, const FrameOutputOptions& output) = 0;
  /// Called from the worker threads, concurrently for different frames, in no particular order.
  virtual void Write(const LabelledFrame& frame) = 0;
};

}  // namespace mocap
