#pragma once
// The segmentation-pairs exporter (docs/export.md "Segmentation pairs"): what SegICP's SegNet was trained
// on (reference/segicp-paper.tex: per image a colour frame and a per-pixel class label), laid out as
// SegNet's CamVid tutorial lays it out (a folder per split, its annotations beside it, list files of
// "image label" pairs):
//
//   DIR/classes.txt                        "id name r g b": 0 background, 1..N, then the ignore value
//   DIR/train.txt, val.txt, test.txt       "<split>/<stem>.png|jpg <split>annot/<stem>.png", relative to DIR
//   DIR/<split>/<stem>.png|jpg             the recorded colour file, linked or copied
//   DIR/<split>annot/<stem>.png            class ids, 8-bit (16-bit when there are more than 254 classes)
//
// <stem> = <scene_id:06d>_<im_id:06d>. Class ids: 0 = background; each object_class of the merged object
// library is one class, numbered 1..N in the order of its lowest object id (stable across exports of
// the same library, whatever the filters keep); several objects may share a class.
// A pixel's class comes from the exported visible masks (VisibleMask: the measured-depth rule when the
// label run had depth, else the model z-buffer):
//  - covered by visible masks of one class only: that class;
//  - covered by visible masks of several classes (measured-depth masks may overlap): the class of the
//    instance the label run's z-buffer (instance PNG) puts in front, when that instance's visible mask
//    covers the pixel; otherwise nothing says which is in front, and the pixel gets the ignore value;
//  - covered by none, where the z-buffer shows an instance the filters left out (not in
//    ExportFrame::instances): the ignore value (255, or 65535 in 16-bit images), which training skips
//    (SegNet/Caffe ignore_label, PyTorch ignore_index), rather than calling a real object background;
//  - otherwise background 0.
#include <array>
#include <cstdint>
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "exporters/dataset/dataset.h"

namespace mocap::exporters {

struct SegPairsOptions {
  /// Pixels of left-out instances: the ignore value (true) or background (false).
  bool ignore_left_out = true;
  int threads = 0;  ///< frames written in parallel; 0: one per core
  void check() const;
};

/// One class of the export.
struct SegClass {
  int id = 0;                       ///< 1..N
  std::string name;                 ///< the object_class
  std::array<uint8_t, 3> rgb{};     ///< palette colour (SegClassColourRgb)
  std::vector<int> object_ids;      ///< objects of the class, ascending
};

/// The classes of `library`: one per object_class, ids 1..N by lowest object id.
std::vector<SegClass> SegClasses(const pipeline::ObjectLibrary& library);

/// PASCAL VOC's colour map (VOCdevkit labelcolormap: bits of the id spread over R, G, B): 0 black,
/// 1 (128,0,0), 2 (0,128,0), ..., 255 (224,224,192), VOC's own colour for its ignore label.
std::array<uint8_t, 3> SegClassColourRgb(int id);

/// One kept instance of a frame, for SegClassImage.
struct SegInstanceMask {
  int class_id = 0;                               ///< 1..N
  uint16_t instance_id = 0;                       ///< the label run's instance id
  PixelRect rect;                                 ///< the mask's crop in the image
  const std::vector<uint8_t>* visible = nullptr;  ///< rect-sized, 1 = visible; not owned
};

/// The class-id image of one frame by the rules above (exposed for tests). `instance_ids` is the label
/// run's instance PNG (CV_16UC1, the model z-buffer); `kept` the frame's exported instances; the result
/// is CV_8UC1 when `ignore_value` is 255, else CV_16UC1. Instance ids in `instance_ids` that are not in
/// `kept` count as left out (ignore_left_out).
cv::Mat SegClassImage(const cv::Mat& instance_ids, const std::vector<SegInstanceMask>& kept, int ignore_value,
                      bool ignore_left_out = true);

/// Writes the dataset as segmentation pairs into `dir` (normally an export's .partial folder). Frames
/// without a colour image are left out (noted). Throws InputError naming the file on a failed write or
/// an unreadable input (a label run without masks or instance PNGs).
WriteSummary WriteSegPairs(const Dataset& dataset, const std::filesystem::path& dir, const SegPairsOptions& options = {});

}  // namespace mocap::exporters
