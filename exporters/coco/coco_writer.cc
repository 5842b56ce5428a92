#include "exporters/coco/coco_writer.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <thread>

#include "core/check.h"
#include "exporters/dataset/parallel.h"
#include "exporters/coco/coco_rle.h"
#include "session/durable_file.h"

namespace mocap::exporters {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kSplits[] = {"train", "val", "test"};
constexpr size_t kFramesPerBatch = 256;  ///< frames converted in parallel before their JSON is appended

json Vec3(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

/// BOP models_info style (formats.md §1): each non-identity rotation of a discrete symmetry as a 4x4
/// row-major matrix in mm (a rotation about an axis through offset o: t = o - R o); continuous ones as
/// axis + offset (mm).
json SymmetriesJson(const pipeline::LibraryObject& object, pipeline::ObjectSymmetry::Type type) {
  json out = json::array();
  for (const pipeline::ObjectSymmetry& s : object.symmetries) {
    if (s.type != type) continue;
    if (type == pipeline::ObjectSymmetry::Type::kContinuous) {
      out.push_back({{"axis", Vec3(s.axis)}, {"offset", Vec3(s.offset_m * 1000.0)}});
      continue;
    }
    const int order = static_cast<int>(std::lround(360.0 / s.angle_deg));
    for (int k = 1; k < order; ++k) {
      const Eigen::Matrix3d R = Eigen::AngleAxisd(k * s.angle_deg * M_PI / 180.0, s.axis.normalized()).toRotationMatrix();
      const Eigen::Vector3d t_mm = (s.offset_m - R * s.offset_m) * 1000.0;
      json m = json::array();
      for (int r = 0; r < 3; ++r) m.insert(m.end(), {R(r, 0), R(r, 1), R(r, 2), t_mm(r)});
      m.insert(m.end(), {0.0, 0.0, 0.0, 1.0});
      out.push_back(std::move(m));
    }
  }
  return out;
}

json CategoryJson(const pipeline::LibraryObject& object) {
  return {{"id", object.id},
          {"name", object.name},
          {"supercategory", object.object_class},
          {"mesh", object.mesh_path.filename().string()},
          {"symmetries_discrete", SymmetriesJson(object, pipeline::ObjectSymmetry::Type::kDiscrete)},
          {"symmetries_continuous", SymmetriesJson(object, pipeline::ObjectSymmetry::Type::kContinuous)}};
}

json CameraJson(const ExportScene& scene) {
  const PinholeCamera& c = scene.color_camera;
  return {{"id", scene.scene_id}, {"name", scene.name}, {"model", scene.camera_model},
          {"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy},
          {"dist", c.dist}, {"K", {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0}}};
}

std::string ImageFileName(const ExportScene& scene, const ExportFrame& frame) {
  char stem[32];
  std::snprintf(stem, sizeof(stem), "%06d_%06d", scene.scene_id, frame.im_id);
  return stem + frame.color_path.extension().string();
}

json ImageJson(const ExportScene& scene, const ExportFrame& frame, int64_t id, const std::string& file_name) {
  return {{"id", id}, {"file_name", file_name}, {"width", scene.color_camera.width},
          {"height", scene.color_camera.height}, {"camera_id", scene.scene_id},
          {"session", scene.session_dir.filename().string()}, {"camera", scene.camera}, {"frame", frame.frame},
          {"index", frame.index}, {"stamp_ns", frame.stamp_ns}, {"scene_id", scene.scene_id}, {"im_id", frame.im_id}};
}

/// The label's pose, object (mesh) to camera, OpenCV axes; null for an instance without one.
json PoseJson(const pipeline::LabelRecord& r) {
  if (!r.has_pose) return nullptr;
  const Eigen::Matrix3d R = r.T_camera_mesh().rotation_matrix();
  json rows = json::array();
  for (int i = 0; i < 3; ++i) rows.insert(rows.end(), {R(i, 0), R(i, 1), R(i, 2)});
  return {{"rvec", Vec3(r.rvec)}, {"t_m", Vec3(r.t_m)}, {"R", std::move(rows)},
          {"quat_wxyz", {r.quat_wxyz(0), r.quat_wxyz(1), r.quat_wxyz(2), r.quat_wxyz(3)}},
          {"direction", "object_to_camera"}};
}

/// The label's bbox_obj (BOP: w = x_max - x_min) as a COCO box (w = x_max - x_min + 1), so both boxes
/// of an annotation share one convention; null when the silhouette is empty.
json AmodalBoxJson(const pipeline::LabelRecord& r) {
  const auto& b = r.bbox_obj;
  if (b[2] < 0 || b[3] < 0) return nullptr;
  return {static_cast<double>(b[0]), static_cast<double>(b[1]), static_cast<double>(b[2] + 1), static_cast<double>(b[3] + 1)};
}

struct FrameOutput {
  json image;
  std::vector<json> annotations;  ///< without "id": ids are counted when the frames are appended in order
  int64_t invisible_left_out = 0, ignored = 0;
  bool linked = false;
};

/// The annotation of one instance, or nothing when it shows no pixel and those are left out.
std::optional<json> AnnotationJson(const ExportInstance& instance, const ObjectMasks& masks, const ExportScene& scene,
                                   int64_t image_id, const CocoOptions& options) {
  const pipeline::LabelRecord& r = instance.record;
  static const std::vector<uint8_t> kNone;
  const std::vector<uint8_t>& visible = masks.rect.empty() ? kNone : VisibleMask(masks, r);
  const int width = scene.color_camera.width, height = scene.color_camera.height;
  const CocoRle rle = EncodeCocoRle(visible, masks.rect, width, height);
  const int64_t area = CocoRleArea(rle);
  if (area == 0 && !options.keep_invisible) return std::nullopt;
  json a = {{"image_id", image_id}, {"category_id", r.object},
            {"segmentation", {{"size", {height, width}}, {"counts", CocoRleString(rle.counts)}}},
            {"area", area}, {"bbox", CocoRleBox(rle)}, {"iscrowd", 0}, {"pose", PoseJson(r)},
            {"bbox_amodal", AmodalBoxJson(r)}, {"visib_fract", r.visib_fract}, {"instance", r.instance},
            {"verdict", instance.verdict.empty() ? json(nullptr) : json(instance.verdict)},
            {"verdict_reason", instance.verdict.empty() ? json(nullptr) : json(instance.verdict_reason)}};
  if (options.write_ignore) a["ignore"] = r.visib_fract < options.ignore_below_visib_fract;
  return a;
}

/// Places the frame's colour image and converts its instances. Runs on worker threads: reads only.
FrameOutput ConvertFrame(const Dataset& dataset, size_t frame_index, const fs::path& dir, const CocoOptions& options) {
  const ExportFrame& frame = dataset.frames[frame_index];
  const ExportScene& scene = dataset.scene_of(frame);
  const int64_t image_id = static_cast<int64_t>(frame_index) + 1;
  if (frame.color_path.empty())
    throw InputError(scene.session_dir.string(), Str("camera ", scene.camera, " record ", frame.index,
                                                     " has no colour image; a COCO dataset needs one per frame"));
  FrameOutput out;
  const std::string file_name = ImageFileName(scene, frame);
  out.linked = LinkOrCopyFile(frame.color_path, dir / "images" / frame.split / file_name);
  out.image = ImageJson(scene, frame, image_id, file_name);
  const std::vector<ObjectMasks> masks = ReadFrameMasks(scene, frame);
  for (size_t k = 0; k < frame.instances.size(); ++k) {
    const pipeline::LabelRecord& r = frame.instances[k].record;
    if (dataset.objects.FindId(r.object) == nullptr)
      throw InputError(scene.labels.labels_jsonl().string(), Str("record ", frame.index, " instance ", r.instance,
                                                                 ": object id ", r.object, " is not in the object library"));
    std::optional<json> a = AnnotationJson(frame.instances[k], masks[k], scene, image_id, options);
    if (!a) {
      ++out.invisible_left_out;
      continue;
    }
    if (a->contains("ignore") && (*a)["ignore"].get<bool>()) ++out.ignored;
    out.annotations.push_back(std::move(*a));
  }
  return out;
}

/// One split's file as it grows: the images and annotations arrays' elements, comma-separated.
struct SplitText {
  std::string images, annotations;
  std::set<size_t> scenes;
};

void Append(std::string& list, const json& element) {
  if (!list.empty()) list += ',';
  list += element.dump();
}

/// The instances file: keys in sorted order, as nlohmann::json would write the whole document.
std::string SplitDocument(const Dataset& dataset, const std::string& split, const SplitText& text) {
  json cameras = json::array(), categories = json::array();
  for (size_t s : text.scenes) cameras.push_back(CameraJson(dataset.scenes[s]));
  std::vector<const pipeline::LibraryObject*> objects;
  for (const pipeline::LibraryObject& o : dataset.objects.objects) objects.push_back(&o);
  std::sort(objects.begin(), objects.end(), [](const auto* a, const auto* b) { return a->id < b->id; });
  for (const pipeline::LibraryObject* o : objects) categories.push_back(CategoryJson(*o));
  const json info = {{"description", "mocaplabel COCO export"}, {"split", split}, {"version", "1.0"},
                     {"pose_extension", "annotations[].pose: object (mesh) to camera, OpenCV axes; rvec radians, t_m metres"}};
  return Str("{\"annotations\":[", text.annotations, "],\"cameras\":", cameras.dump(), ",\"categories\":",
             categories.dump(), ",\"images\":[", text.images, "],\"info\":", info.dump(), ",\"licenses\":[]}");
}

struct Totals {
  int64_t annotation_id = 0;  ///< the last annotation id given
  int64_t copied = 0, invisible = 0, ignored = 0;
};

/// Appends a converted batch (frames begin.. in dataset order) to the split texts, numbering annotations.
void AppendBatch(const Dataset& dataset, size_t begin, std::vector<FrameOutput>& batch,
                 std::map<std::string, SplitText>& splits, Totals& totals, WriteSummary& summary) {
  for (size_t k = 0; k < batch.size(); ++k) {
    const ExportFrame& frame = dataset.frames[begin + k];
    FrameOutput& out = batch[k];
    SplitText& text = splits.at(frame.split);
    text.scenes.insert(frame.scene);
    Append(text.images, out.image);
    for (json& a : out.annotations) {
      a["id"] = ++totals.annotation_id;
      Append(text.annotations, a);
    }
    totals.copied += out.linked ? 0 : 1, totals.invisible += out.invisible_left_out, totals.ignored += out.ignored;
    summary.images_per_split[frame.split] += 1;
    summary.annotations_per_split[frame.split] += static_cast<int64_t>(out.annotations.size());
  }
}

void AddNotes(const Totals& totals, const CocoOptions& options, WriteSummary& summary) {
  if (totals.copied > 0)
    summary.notes.push_back(Str("colour copied for ", totals.copied, " images: the file system has no hard links"));
  if (totals.invisible > 0)
    summary.notes.push_back(Str(totals.invisible, " instances with no visible pixel left out (keep_invisible)"));
  if (totals.ignored > 0)
    summary.notes.push_back(Str(totals.ignored, " annotations marked ignore (visib_fract < ",
                                options.ignore_below_visib_fract, ")"));
}

void MakeDirectory(const fs::path& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw InputError(dir.string(), Str("cannot create the folder: ", error.message()));
}

}  // namespace

void CocoOptions::check() const {
  if (!(ignore_below_visib_fract >= 0.0 && ignore_below_visib_fract <= 1.0))
    throw InputError("coco options", Str("ignore_below_visib_fract ", ignore_below_visib_fract, " is outside 0..1"));
  if (threads < 0 || threads > 1024) throw InputError("coco options", Str("threads ", threads, " is outside 0..1024"));
}

WriteSummary WriteCoco(const Dataset& dataset, const fs::path& dir, const CocoOptions& options) {
  options.check();
  std::map<std::string, SplitText> splits;
  for (const std::string& split : dataset.splits()) {
    splits[split];
    MakeDirectory(dir / "images" / split);
  }
  for (const ExportFrame& f : dataset.frames)
    MOCAP_CHECK(splits.count(f.split) == 1, "frame ", f.index, " has split '", f.split, "': SelectFrames assigns splits");
  MakeDirectory(dir / "annotations");
  WriteSummary summary;
  summary.format = "coco";
  Totals totals;
  std::vector<FrameOutput> batch;
  // In batches, so that only one batch of frames' JSON trees is held; the text of the lists grows.
  for (size_t begin = 0; begin < dataset.frames.size(); begin += kFramesPerBatch) {
    const size_t end = std::min(dataset.frames.size(), begin + kFramesPerBatch);
    batch.assign(end - begin, FrameOutput{});
    ParallelFor(end - begin, options.threads,
                [&](size_t k) { batch[k] = ConvertFrame(dataset, begin + k, dir, options); });
    AppendBatch(dataset, begin, batch, splits, totals, summary);
  }
  for (const char* split : kSplits) {
    if (splits.count(split) == 0) continue;
    WriteFileAtomically(dir / "annotations" / Str("instances_", split, ".json"), SplitDocument(dataset, split, splits[split]));
    ++summary.files;
  }
  summary.images = static_cast<int64_t>(dataset.frames.size());
  summary.annotations = totals.annotation_id;
  summary.files += summary.images;
  AddNotes(totals, options, summary);
  return summary;
}

}  // namespace mocap::exporters
