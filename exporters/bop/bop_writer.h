#pragma once
// The BOP exporter (docs/export.md "BOP"): the layout and files bop_toolkit reads
// (docs/bop_datasets_format.md, bop_toolkit_lib/inout.py), one BOP scene per session and camera:
//
//   DIR/camera.json                          the first scene's intrinsics (per image: scene_camera.json)
//   DIR/models/obj_OOOOOO.ply, models_info.json   meshes in mm, diameter, extents, symmetries
//   DIR/test_targets_bop19.json              instances with visib_fract >= 0.1 (of the test split)
//   DIR/<split>/<scene_id:06d>/rgb/<im_id:06d>.png|jpg       the recorded files, linked or copied
//   DIR/<split>/<scene_id:06d>/depth/<im_id:06d>.png         uint16, x depth_scale = mm
//   DIR/<split>/<scene_id:06d>/mask{,_visib}/<im_id:06d>_<gt_id:06d>.png   0/255
//   DIR/<split>/<scene_id:06d>/scene_camera.json, scene_gt.json, scene_gt_info.json
#include <filesystem>

#include "exporters/dataset/dataset.h"

namespace mocap::exporters {

struct BopOptions {
  bool write_depth = true;
  bool write_masks = true;  ///< mask/ and mask_visib/
  bool write_models = true;
  /// Depth that must be re-encoded (not registered to colour, or not a 16-bit PNG) is written in these
  /// millimetres per unit (BOP's depth_scale); registered 16-bit PNG depth is linked as recorded, with
  /// depth_scale = its unit in mm.
  double converted_depth_scale_mm = 1.0;
  int threads = 0;  ///< 0: one per core
  void check() const;
};

/// Writes the dataset as BOP into `dir` (normally an export's .partial folder). Throws InputError
/// naming the file on a failed write or an unreadable input.
WriteSummary WriteBop(const Dataset& dataset, const std::filesystem::path& dir, const BopOptions& options);

}  // namespace mocap::exporters
