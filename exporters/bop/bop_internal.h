#pragma once
// Parts of the BOP writer (bop_writer.cc): one scene folder's frames, the models, and BOP's JSON layout.
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>

#include "exporters/bop/bop_writer.h"

namespace mocap::exporters::bop {

/// bop_toolkit's save_json layout: one "<integer key>": value per line, keys in numeric order, so that
/// diffs of scene files stay readable. `entries` keyed by im_id / obj_id.
std::string BopJsonText(const std::map<int, nlohmann::json>& entries);
/// A JSON list `[...]` of 0..n BOP objects written one value per line (the targets file).
std::string BopJsonListText(const std::vector<nlohmann::json>& items);

/// The per-image JSON of one scene folder (one split of one scene), filled as frames are written.
struct SceneJson {
  std::mutex mutex;
  std::map<int, nlohmann::json> camera, gt, gt_info;
};

/// Writes one frame's images into `scene_dir` and its entries into `json`. Thread-safe across frames.
/// Returns the files created.
int64_t WriteBopFrame(const Dataset& dataset, const ExportFrame& frame, const std::filesystem::path& scene_dir,
                      const BopOptions& options, SceneJson& json);

/// models/obj_OOOOOO.ply (mm) and models/models_info.json of every object of the dataset's library.
int64_t WriteBopModels(const Dataset& dataset, const std::filesystem::path& models_dir, std::vector<std::string>& notes);

}  // namespace mocap::exporters::bop
