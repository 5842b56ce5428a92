#include "session/import/bop_import.h"


#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>

#include "core/check.h"
#include "session/import/bop_scene.h"
#include "session/import/image_check.h"
#include "session/writer.h"

namespace mocap::import {
namespace {

// Frames sharing one exact camera model and depth scale.
struct CameraGroup {
  std::string camera, tracker;
  std::vector<const BopFrame*> frames;
  std::vector<std::string> bodies;  // sorted
};

bool SameCamera(const BopFrame& a, const BopFrame& b) {
  return a.camera.fx == b.camera.fx && a.camera.fy == b.camera.fy && a.camera.cx == b.camera.cx &&
         a.camera.cy == b.camera.cy && a.camera.width == b.camera.width && a.camera.height == b.camera.height &&
         a.depth_scale_mm == b.depth_scale_mm;
}

std::vector<CameraGroup> GroupFrames(const BopScene& scene) {
  std::vector<CameraGroup> groups;
  for (const auto& frame : scene.frames) {
    auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return SameCamera(*g.frames.front(), frame); });
    if (it == groups.end()) {
      const std::string suffix = groups.empty() ? "" : Str("_", groups.size());
      groups.push_back({"bop" + suffix, "objects" + suffix, {}, {}});
      it = groups.end() - 1;
    }
    it->frames.push_back(&frame);
  }
  for (auto& g : groups) {
    std::set<std::string> bodies;
    for (const auto* f : g.frames)
      for (const auto& o : f->objects) bodies.insert(BopBodyName(o.obj_id, o.instance));
    g.bodies.assign(bodies.begin(), bodies.end());
  }
  return groups;
}

int64_t StampNs(int im_id, double rate_hz) { return std::llround(static_cast<double>(im_id) * 1e9 / rate_hz); }

nlohmann::json ObjectList(const BopScene& scene) {
  nlohmann::json objects = nlohmann::json::array();
  for (const auto& model : scene.models) {
    nlohmann::json bodies = nlohmann::json::array();
    int instances = 0;
    for (const auto& f : scene.frames)
      instances = std::max(instances, static_cast<int>(std::count_if(f.objects.begin(), f.objects.end(),
                                                                      [&](const auto& o) { return o.obj_id == model.obj_id; })));
    for (int k = 0; k < instances; ++k) bodies.push_back(BopBodyName(model.obj_id, k));
    objects.push_back({{"id", model.obj_id}, {"name", BopObjectName(model.obj_id)}, {"mesh", model.mesh.string()},
                       {"unit", "mm"}, {"diameter_m", model.diameter_m}, {"tracker_bodies", bodies}});
  }
  return objects;
}

std::vector<BopObject> Objects(const nlohmann::json& list) {
  std::vector<BopObject> objects;
  for (const auto& o : list)
    objects.push_back({o["id"].get<int>(), o["name"].get<std::string>(), o["mesh"].get<std::string>(),
                       o["diameter_m"].get<double>(), o["tracker_bodies"].get<std::vector<std::string>>()});
  return objects;
}

void WriteGroup(SessionWriter& writer, const CameraGroup& group, const BopImportOptions& options, Progress& progress,
                ImportSummary& summary) {
  std::map<std::string, std::vector<TrackerRecord>> by_body;
  for (const auto* f : group.frames) {
    progress.Advance();
    CameraFrameRecord record;
    record.frame = f->im_id;
    record.stamp_ns = StampNs(f->im_id, options.frame_rate_hz);
    record.source_id = std::to_string(f->im_id);
    writer.AddCameraFrameFiles(group.camera, record, f->rgb, f->depth);
    ++summary.camera_records;
    summary.frames_with_color_and_depth += !f->depth.empty();
    summary.frames_color_only += f->depth.empty();
    for (const auto& body : group.bodies) {
      TrackerRecord r;
      r.body = body;
      r.status = PoseStatus::kMissing;  // not annotated in this frame unless found below
      r.device_frame = f->im_id;
      r.stamp_ns = record.stamp_ns;
      for (const auto& o : f->objects)
        if (BopBodyName(o.obj_id, o.instance) == body) {
          r.status = PoseStatus::kValid;
          r.T_frame_body = o.T_camera_object;
        }
      by_body[body].push_back(r);
    }
  }
  // Known poses sit exactly at frame times; no gap between frames is a tracker dropout.
  const int64_t no_gap_limit = std::numeric_limits<int64_t>::max();
  for (const auto& [body, records] : by_body) WriteBodySamples(writer, group.tracker, records, no_gap_limit, summary);
}

}  // namespace

void BopImportOptions::check() const {
  CheckInRange(frame_rate_hz, kBopFrameRateRangeHz, "BopImportOptions::frame_rate_hz");
  MOCAP_CHECK(write_objects, "BopImportOptions::write_objects is not set");
}

std::string BopBodyName(int obj_id, int instance) {
  return instance == 0 ? BopObjectName(obj_id) : Str(BopObjectName(obj_id), "_inst", instance);
}

ImportSummary ImportBop(const std::filesystem::path& scene_dir, const std::filesystem::path& models_dir,
                        const std::filesystem::path& out, const BopImportOptions& options) {
  options.check();
  CheckOutputFolder(out);
  const BopScene scene = ReadBopScene(scene_dir, models_dir);
  if (scene.frames.empty()) throw InputError(scene_dir.string(), "no annotated frame has a colour image in rgb/");
  for (const auto& frame : scene.frames) {
    CheckImportableImage(frame.rgb, false);
    if (!frame.depth.empty()) CheckImportableImage(frame.depth, true);
  }
  const auto groups = GroupFrames(scene);
  SessionManifest manifest;
  manifest.software_version = options.software_version;
  manifest.source = "import bop " + scene.dir.lexically_normal().string();
  for (const auto& g : groups) {
    CameraStreamInfo camera;
    camera.name = g.camera;
    camera.model = "bop";
    camera.color_camera = g.frames.front()->camera;
    camera.depth_camera = g.frames.front()->camera;  // BOP depth is aligned with the colour image
    camera.depth_unit_m = g.frames.front()->depth_scale_mm * 1e-3;
    // A BOP test split ships every few images of a sequence: gaps in im_id are a selection, not drops.
    for (size_t i = 1; i < g.frames.size(); ++i)
      camera.frames_subset = camera.frames_subset || g.frames[i]->im_id != g.frames[i - 1]->im_id + 1;
    manifest.cameras.push_back(camera);
    manifest.trackers.push_back({g.tracker, "bop_ground_truth", "", "camera:" + g.camera, g.bodies});
  }
  const nlohmann::json objects = ObjectList(scene);
  manifest.extra["objects"] = objects;
  manifest.extra["bop"] = {{"scene_id", scene.scene_id}, {"models_dir", std::filesystem::absolute(models_dir).lexically_normal().string()},
                           {"annotated_frames", scene.annotated_frames}, {"frames_without_rgb", scene.frames_without_rgb},
                           {"synthetic_frame_rate_hz", options.frame_rate_hz}};

  ImportSummary summary;
  summary.session = out;
  summary.notes.push_back(Str(scene.frames_without_rgb, " annotated frames have no colour image and were skipped"));
  summary.notes.push_back(Str("stamps are synthetic: im_id at ", options.frame_rate_hz, " Hz"));
  if (groups.size() > 1) summary.notes.push_back(Str("cam_K varies: ", groups.size(), " cameras, one per distinct K"));
  PublishSession(out, scene_dir, manifest, [&](SessionWriter& writer, const std::filesystem::path& dir) {
    options.write_objects(dir / "objects.yaml", Objects(objects), manifest.source);
    Progress progress(options.progress, "import", static_cast<int64_t>(scene.frames.size()), "frames");
    for (const auto& g : groups) WriteGroup(writer, g, options, progress, summary);
  });
  return summary;
}

}  // namespace mocap::import
