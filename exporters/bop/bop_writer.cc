// WriteBop: the dataset's frames into BOP scene folders, frames written in parallel (each frame's files
// are its own; the scene JSON is filled under a lock and written once at the end).
#include "exporters/bop/bop_writer.h"

#include <atomic>
#include <exception>
#include <thread>

#include "core/check.h"
#include "exporters/dataset/parallel.h"
#include "exporters/bop/bop_internal.h"
#include "session/durable_file.h"

namespace mocap::exporters {
namespace fs = std::filesystem;
namespace {

/// The folders of one split of one scene, and its JSON.
struct SceneFolder {
  fs::path dir;
  bop::SceneJson json;
};

fs::path SceneDir(const fs::path& root, const std::string& split, int scene_id) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d", scene_id);
  return root / split / name;
}

nlohmann::json CameraJson(const Dataset& d) {
  const ExportScene& s = d.scenes.front();
  const PinholeCamera& c = s.color_camera;
  return {{"cx", c.cx}, {"cy", c.cy}, {"depth_scale", s.depth_unit_m * 1e3}, {"fx", c.fx},
          {"fy", c.fy}, {"height", c.height}, {"width", c.width}};
}

/// BOP19 targets: instances with visib_fract >= 0.1 of the test split (of every frame when the export
/// has no test split), counted per (scene, image, object).
std::string TargetsText(const Dataset& d) {
  const bool has_test = !d.frames.empty() && std::any_of(d.frames.begin(), d.frames.end(), [](const ExportFrame& f) { return f.split == "test"; });
  std::vector<nlohmann::json> targets;
  for (const ExportFrame& f : d.frames) {
    if (has_test && f.split != "test") continue;
    std::map<int, int> count_by_object;
    for (const ExportInstance& i : f.instances)
      if (i.record.has_pose && i.record.visib_fract >= 0.1) ++count_by_object[i.record.object];
    for (const auto& [object, count] : count_by_object)
      targets.push_back({{"im_id", f.im_id}, {"inst_count", count}, {"obj_id", object}, {"scene_id", d.scene_of(f).scene_id}});
  }
  return bop::BopJsonListText(targets);
}

}  // namespace

void BopOptions::check() const {
  if (!(converted_depth_scale_mm > 0)) throw InputError("BopOptions", "converted_depth_scale_mm must be positive");
  if (threads < 0) throw InputError("BopOptions", "threads must be >= 0");
}

WriteSummary WriteBop(const Dataset& dataset, const fs::path& dir, const BopOptions& options) {
  options.check();
  WriteSummary summary;
  summary.format = "bop";
  std::map<std::pair<std::string, size_t>, std::unique_ptr<SceneFolder>> folders;
  std::vector<SceneFolder*> folder_of_frame;
  for (const ExportFrame& f : dataset.frames) {
    auto& folder = folders[{f.split, f.scene}];
    if (!folder) {
      folder = std::make_unique<SceneFolder>();
      folder->dir = SceneDir(dir, f.split, dataset.scene_of(f).scene_id);
      for (const char* sub : {"rgb", "depth", "mask", "mask_visib"}) fs::create_directories(folder->dir / sub);
    }
    folder_of_frame.push_back(folder.get());
    ++summary.images, ++summary.images_per_split[f.split];
    for (const ExportInstance& i : f.instances)
      if (i.record.has_pose) ++summary.annotations, ++summary.annotations_per_split[f.split];
  }
  const int threads = WorkerThreads(options.threads);
  std::atomic<int64_t> files{0};
  ParallelFor(dataset.frames.size(), threads, [&](size_t i) {
    SceneFolder& folder = *folder_of_frame[i];
    files += bop::WriteBopFrame(dataset, dataset.frames[i], folder.dir, options, folder.json);
  });
  for (auto& [key, folder] : folders) {
    WriteFileAtomically(folder->dir / "scene_camera.json", bop::BopJsonText(folder->json.camera));
    WriteFileAtomically(folder->dir / "scene_gt.json", bop::BopJsonText(folder->json.gt));
    WriteFileAtomically(folder->dir / "scene_gt_info.json", bop::BopJsonText(folder->json.gt_info));
    files += 3;
  }
  if (!dataset.scenes.empty()) WriteFileAtomically(dir / "camera.json", CameraJson(dataset).dump(2) + "\n");
  WriteFileAtomically(dir / "test_targets_bop19.json", TargetsText(dataset));
  if (options.write_models) files += bop::WriteBopModels(dataset, dir / "models", summary.notes);
  summary.files = files + 2;
  return summary;
}

}  // namespace mocap::exporters
