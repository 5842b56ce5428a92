// WriteTum: the dataset's frames as TUM RGB-D sequence folders (tum_writer.h; formats.md §6). Images are
// written in parallel, one frame per task; the list and trajectory files are assembled afterwards in
// stamp order, because TUM's readers (and ours: session/import/tum.cc) require sorted stamps.
#include "exporters/tum/tum_writer.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <thread>

#include "core/check.h"
#include "core/text.h"
#include "exporters/dataset/parallel.h"
#include "label/label_png.h"
#include "session/durable_file.h"
#include "session/image_io.h"
#include "session/png_write.h"

namespace mocap::exporters {
namespace fs = std::filesystem;
namespace {

/// The frames of one sequence folder, in stamp order, with their file stems.
struct Sequence {
  fs::path dir;
  size_t scene = 0;
  std::vector<const ExportFrame*> frames;
  std::vector<std::string> stems;      ///< unique per sequence: the stamp text, "_<index>" on a clash
  std::vector<std::string> rgb, depth;  ///< relative paths written per frame ("" when none)
};

/// Object names become file names: anything but [A-Za-z0-9._-] is replaced by '_'.
std::string FileSafe(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') c = '_';
  return name.empty() ? std::string("_") : name;
}

/// A scene name in a '#' comment line: control characters (a newline would end the comment) become '?'.
std::string CommentSafe(std::string text) {
  for (char& c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  return text;
}

/// rgb/<stem>.<ext>: the recorded file linked or copied, or a JPEG re-encoded as PNG when asked.
std::string WriteColor(const ExportFrame& frame, const Sequence& seq, size_t k, const TumExportOptions& o) {
  if (frame.color_path.empty()) return {};
  const std::string ext = LowerExtension(frame.color_path);
  if (ext == ".jpg" && o.jpeg_to_png) {
    // The one colour reader (a truncated JPEG is an error naming the file, not a grey half image).
    const cv::Mat bgr = ReadColor(frame.color_path);
    std::vector<uint8_t> png;
    cv::imencode(".png", bgr, png);
    WriteFileBytes(seq.dir / "rgb" / (seq.stems[k] + ".png"), png);
    return "rgb/" + seq.stems[k] + ".png";
  }
  LinkOrCopyFile(frame.color_path, seq.dir / "rgb" / (seq.stems[k] + ext));
  return "rgb/" + seq.stems[k] + ext;
}

/// depth/<stem>.png in TUM units. A registered 16-bit PNG already in 1/5000 m (a TUM import) is linked
/// as recorded; anything else goes through ColorAlignedDepthM and is quantised to 1/5000 m, values
/// beyond 65535 units (13.1 m) written as 0 = missing.
std::string WriteDepth(const ExportScene& scene, const ExportFrame& frame, const Sequence& seq, size_t k) {
  if (frame.depth_path.empty()) return {};
  const fs::path file = seq.dir / "depth" / (seq.stems[k] + ".png");
  if (scene.depth_registered_to_color && LowerExtension(frame.depth_path) == ".png" &&
      std::abs(scene.depth_unit_m * kTumDepthPerMetre - 1.0) < 1e-12) {
    LinkOrCopyFile(frame.depth_path, file);
    return "depth/" + seq.stems[k] + ".png";
  }
  const cv::Mat depth_m = ColorAlignedDepthM(scene, frame);
  if (depth_m.empty()) return {};
  cv::Mat units(depth_m.rows, depth_m.cols, CV_16UC1);
  for (int v = 0; v < depth_m.rows; ++v)
    for (int u = 0; u < depth_m.cols; ++u) {
      const double value = std::round(static_cast<double>(depth_m.at<float>(v, u)) * kTumDepthPerMetre);
      units.at<uint16_t>(v, u) = value > 0 && value <= 65535 ? static_cast<uint16_t>(value) : 0;  // NaN too
    }
  WriteFileBytes(file, EncodeGray16Png(units));
  return "depth/" + seq.stems[k] + ".png";
}

/// TUM's list header ("# color images" / "# file: '...bag'" / "# timestamp filename"), the bag line
/// replaced by where the data came from.
std::string Header(const std::string& title, const ExportScene& scene, const std::string& columns) {
  return Str("# ", title, "\n# mocaplabel export of '", CommentSafe(scene.name), "' (scene ", scene.scene_id,
             "), session clock\n# ", columns, "\n");
}

std::string ListText(const std::string& title, const ExportScene& scene, const Sequence& seq,
                     const std::vector<std::string>& files) {
  std::string text = Header(title, scene, "timestamp filename");
  for (size_t k = 0; k < seq.frames.size(); ++k)
    if (!files[k].empty()) text += TumStampText(seq.frames[k]->stamp_ns) + " " + files[k] + "\n";
  return text;
}

bool Tracked(const Sequence& seq) {
  return std::any_of(seq.frames.begin(), seq.frames.end(), [](const ExportFrame* f) { return f->T_tracker_camera.has_value(); });
}

std::string GroundTruthText(const ExportScene& scene, const Sequence& seq, bool tracked) {
  std::string text = Header(tracked ? "ground truth trajectory (colour optical centre in the tracker frame)"
                                    : "ground truth trajectory: none, the camera is not tracked",
                            scene, "timestamp tx ty tz qx qy qz qw");
  for (const ExportFrame* f : seq.frames)
    if (f->T_tracker_camera) text += TumPoseLine(f->stamp_ns, *f->T_tracker_camera) + "\n";
  return text;
}

/// One trajectory file per object instance of the sequence: T_tracker_mesh = T_tracker_camera *
/// T_camera_mesh per labelled frame with both poses (T_camera_mesh alone when untracked). Returns the
/// pose lines written.
int64_t WriteObjects(const Dataset& dataset, const Sequence& seq, bool tracked, int64_t& files) {
  const ExportScene& scene = dataset.scenes[seq.scene];
  std::map<std::pair<int, int>, std::string> lines;  // (object id, instance) -> pose lines
  std::map<int, std::set<int>> instances_of_object;
  int64_t poses = 0;
  for (const ExportFrame* f : seq.frames)
    for (const ExportInstance& instance : f->instances) {
      const pipeline::LabelRecord& r = instance.record;
      if (!r.has_pose || (tracked && !f->T_tracker_camera)) continue;
      const Rigid3d T_world_mesh = tracked ? *f->T_tracker_camera * r.T_camera_mesh() : r.T_camera_mesh();
      lines[{r.object, r.instance}] += TumPoseLine(f->stamp_ns, T_world_mesh) + "\n";
      instances_of_object[r.object].insert(r.instance);
      ++poses;
    }
  const fs::path folder = seq.dir / (tracked ? "objects" : "objects_in_camera");
  if (!lines.empty()) fs::create_directories(folder);
  for (const auto& [key, text] : lines) {
    const pipeline::LibraryObject* object = dataset.objects.FindId(key.first);
    const std::string name = object ? object->name : Str("object_", key.first);
    const bool several = instances_of_object[key.first].size() > 1;
    const std::string file = FileSafe(several ? Str(name, "_", key.second) : name) + ".txt";
    const std::string title = Str("object '", CommentSafe(name), "' (id ", key.first, ") instance ", key.second,
                                  tracked ? ": mesh frame in the tracker frame (T_tracker_mesh)"
                                          : ": mesh frame in the colour camera frame (T_camera_mesh; camera not tracked)");
    WriteFileAtomically(folder / file, Header(title, scene, "timestamp tx ty tz qx qy qz qw") + text);
    ++files;
  }
  return poses;
}

/// camera.txt: the colour intrinsics the labels were made with. TUM publishes "fx fy cx cy d0 d1 d2 d3
/// d4" on its web page only; here they travel with the sequence (import with --intrinsics fx,fy,cx,cy).
std::string CameraText(const ExportScene& scene) {
  const PinholeCamera& c = scene.color_camera;
  std::string text = Header("colour camera intrinsics (pixels; distortion in OpenCV order k1 k2 p1 p2 k3 k4 k5 k6)",
                            scene, "width height fx fy cx cy d0 d1 d2 d3 d4 d5 d6 d7");
  char line[512];
  std::snprintf(line, sizeof line, "%d %d %.9g %.9g %.9g %.9g", c.width, c.height, c.fx, c.fy, c.cx, c.cy);
  text += line;
  for (double d : c.dist) text += Str(" ", d);
  return text + "\n";
}

/// Groups the frames into sequences (split, scene) and gives each frame a unique file stem.
std::vector<Sequence> PlanSequences(const Dataset& dataset, const fs::path& dir) {
  std::map<std::pair<std::string, size_t>, Sequence> by_key;
  for (const ExportFrame& f : dataset.frames) {
    Sequence& seq = by_key[{f.split, f.scene}];
    seq.scene = f.scene;
    char scene_folder[32];
    std::snprintf(scene_folder, sizeof scene_folder, "%06d", dataset.scenes[f.scene].scene_id);
    seq.dir = dir / f.split / scene_folder;
    seq.frames.push_back(&f);
  }
  std::vector<Sequence> out;
  for (auto& [key, seq] : by_key) {
    std::stable_sort(seq.frames.begin(), seq.frames.end(), [](auto* a, auto* b) { return a->stamp_ns < b->stamp_ns; });
    std::set<std::string> used;
    for (const ExportFrame* f : seq.frames) {
      std::string stem = TumStampText(f->stamp_ns);
      if (!used.insert(stem).second) used.insert(stem = Str(stem, "_", f->index));  // two frames, one stamp
      seq.stems.push_back(stem);
    }
    seq.rgb.resize(seq.frames.size());
    seq.depth.resize(seq.frames.size());
    out.push_back(std::move(seq));
  }
  return out;
}

/// The list, trajectory and camera files of one sequence, after its images; counts into `summary`.
void WriteSequenceFiles(const Dataset& dataset, const Sequence& seq, const TumExportOptions& options, WriteSummary& summary) {
  const ExportScene& scene = dataset.scenes[seq.scene];
  const std::string& split = seq.frames.front()->split;
  const bool tracked = Tracked(seq);
  WriteFileAtomically(seq.dir / "rgb.txt", ListText("color images", scene, seq, seq.rgb));
  if (options.write_depth) WriteFileAtomically(seq.dir / "depth.txt", ListText("depth maps", scene, seq, seq.depth));
  WriteFileAtomically(seq.dir / "groundtruth.txt", GroundTruthText(scene, seq, tracked));
  WriteFileAtomically(seq.dir / "camera.txt", CameraText(scene));
  summary.files += 3 + (options.write_depth ? 1 : 0);
  if (options.write_objects) {
    const int64_t poses = WriteObjects(dataset, seq, tracked, summary.files);
    summary.annotations += poses;
    summary.annotations_per_split[split] += poses;
  }
  int64_t untracked_frames = 0;
  for (size_t k = 0; k < seq.frames.size(); ++k) {
    const int64_t written = !seq.rgb[k].empty() + !seq.depth[k].empty();
    summary.files += written;
    if (written > 0) ++summary.images, ++summary.images_per_split[split];
    untracked_frames += tracked && !seq.frames[k]->T_tracker_camera;
  }
  if (!tracked)
    summary.notes.push_back(Str(scene.name, ": camera not tracked: no groundtruth, object poses in the camera frame (objects_in_camera/)"));
  if (untracked_frames > 0)
    summary.notes.push_back(Str(scene.name, ": ", untracked_frames, " frames without a camera pose: images listed, no groundtruth or object lines"));
}

}  // namespace

void TumExportOptions::check() const {
  if (threads < 0) throw InputError("TumExportOptions", "threads must be >= 0");
}

std::string TumStampText(int64_t stamp_ns) {
  const bool negative = stamp_ns < 0;
  const uint64_t magnitude = negative ? 0 - static_cast<uint64_t>(stamp_ns) : static_cast<uint64_t>(stamp_ns);
  char text[48];
  std::snprintf(text, sizeof text, "%s%llu.%09llu", negative ? "-" : "", static_cast<unsigned long long>(magnitude / 1'000'000'000),
                static_cast<unsigned long long>(magnitude % 1'000'000'000));
  return text;
}

std::string TumPoseLine(int64_t stamp_ns, const Rigid3d& T_world_frame) {
  // Values that print as zero are written as 0, never "-0.000...", so equal poses give equal lines.
  auto zeroed = [](double value, double half_digit) { return std::abs(value) < half_digit ? 0.0 : value; };
  const Eigen::Vector3d& t = T_world_frame.translation();
  const Eigen::Vector4d q = T_world_frame.quat_xyzw();
  char text[256];
  std::snprintf(text, sizeof text, " %.9f %.9f %.9f %.12f %.12f %.12f %.12f", zeroed(t.x(), 5e-10), zeroed(t.y(), 5e-10),
                zeroed(t.z(), 5e-10), zeroed(q[0], 5e-13), zeroed(q[1], 5e-13), zeroed(q[2], 5e-13), zeroed(q[3], 5e-13));
  return TumStampText(stamp_ns) + text;
}

WriteSummary WriteTum(const Dataset& dataset, const fs::path& dir, const TumExportOptions& options) {
  options.check();
  WriteSummary summary;
  summary.format = "tum";
  std::vector<Sequence> sequences = PlanSequences(dataset, dir);
  std::vector<std::pair<Sequence*, size_t>> jobs;
  for (Sequence& seq : sequences) {
    if (!Tracked(seq) && !options.camera_frame_when_untracked)
      throw InputError(dataset.scenes[seq.scene].name,
                       "the camera is not tracked in any exported frame, so TUM's groundtruth.txt would be empty; "
                       "export another format, or allow camera-frame object trajectories (TumExportOptions::camera_frame_when_untracked)");
    for (const char* sub : {"rgb", "depth"}) fs::create_directories(seq.dir / sub);
    for (size_t k = 0; k < seq.frames.size(); ++k) jobs.emplace_back(&seq, k);
  }
  const int threads = WorkerThreads(options.threads);
  ParallelFor(jobs.size(), threads, [&](size_t j) {
    auto& [seq, k] = jobs[j];
    const ExportFrame& frame = *seq->frames[k];
    seq->rgb[k] = WriteColor(frame, *seq, k, options);
    if (options.write_depth) seq->depth[k] = WriteDepth(dataset.scene_of(frame), frame, *seq, k);
  });
  for (const Sequence& seq : sequences) WriteSequenceFiles(dataset, seq, options, summary);
  return summary;
}

}  // namespace mocap::exporters
