#pragma once
// The COCO exporter (docs/export.md "COCO"): one instances file per split, loadable by pycocotools'
// COCO(path), with the 6-DoF pose of every instance as an extension, and the colour images next to it:
//
//   DIR/annotations/instances_<split>.json     split = train, val, test (those present)
//   DIR/images/<split>/<scene_id:06d>_<im_id:06d>.<ext of the recorded colour file>
//
// `file_name` in the images list is relative to DIR/images/<split>/ (as COCO's train2017/ folders).
// Segmentations are compressed RLE (coco_rle.h) of the visible mask (VisibleMask); `area` and `bbox` are
// computed from that RLE as pycocotools computes them. Image and annotation ids are 1-based, counted over
// the whole export in frame order, so they are unique across the split files. The output is a function
// of the dataset and the options only (no dates, sorted keys): the same input gives the same bytes.
#include <filesystem>

#include "exporters/dataset/dataset.h"

namespace mocap::exporters {

struct CocoOptions {
  /// Annotations whose visib_fract is below this get `"ignore": true` (bop_toolkit's scene_gt_coco rule,
  /// 0.1). pycocotools' COCOeval overrides `ignore` with `iscrowd`; mmdetection skips ignored boxes.
  double ignore_below_visib_fract = 0.1;
  /// Write the `ignore` key at all. detectron2's load_coco_json asserts that no annotation has a true
  /// `ignore`: turn this off for detectron2 (or leave weakly visible instances out with the dataset's
  /// min_visib_fract filter).
  bool write_ignore = true;
  /// Keep instances with no visible pixel in the image (segmentation of an empty mask, area 0, bbox
  /// [0, 0, 0, 0]). Off by default: COCOeval counts such a ground truth as a miss that no detection can
  /// match, and training loaders drop zero-sized boxes anyway; their poses remain in the BOP export.
  bool keep_invisible = false;
  /// Frames converted in parallel (mask decoding, RLE, image placement); 0 = hardware threads.
  int threads = 0;
  /// Throws InputError naming the option when a value is out of range.
  void check() const;
};

/// Writes the COCO dataset of `dataset`'s frames into `dir` (created when missing; files already there
/// with the same names are replaced). Every frame must carry a split (train, val or test: SelectFrames).
/// Throws InputError naming the file when a frame has no colour image, its masks cannot be read
/// (ReadFrameMasks) or a write fails.
WriteSummary WriteCoco(const Dataset& dataset, const std::filesystem::path& dir, const CocoOptions& options = {});

}  // namespace mocap::exporters
