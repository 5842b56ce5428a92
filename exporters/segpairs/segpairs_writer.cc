// WriteSegPairs: colour frames and class-id images for SegNet-style training (segpairs_writer.h). Frames
// are written in parallel, one per task; classes.txt and the list files afterwards, in frame order.
#include "exporters/segpairs/segpairs_writer.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "core/check.h"
#include "core/text.h"
#include "exporters/dataset/parallel.h"
#include "label/label_png.h"
#include "session/durable_file.h"

namespace mocap::exporters {
namespace fs = std::filesystem;
namespace {

constexpr int kNoOwner = -1;     // no kept visible mask covers the pixel
constexpr int kConflict = -2;    // visible masks of different classes cover it
constexpr std::array<uint8_t, 3> kIgnoreRgb = {224, 224, 192};  // VOC's colour of its ignore label 255

struct PairPaths {
  std::string image, label;  ///< relative to the export folder; empty when the frame was left out
};

/// Class names are one field of classes.txt: whitespace and control characters become '_'.
std::string FieldSafe(std::string name) {
  for (char& c : name)
    if (std::isspace(static_cast<unsigned char>(c)) || static_cast<unsigned char>(c) < 0x20) c = '_';
  return name.empty() ? std::string("_") : name;
}

bool Covers(const SegInstanceMask& m, int u, int v) {
  return m.rect.contains(u, v) && (*m.visible)[static_cast<size_t>(v - m.rect.y) * m.rect.width + (u - m.rect.x)] != 0;
}

/// Per pixel: the index in `kept` of the first instance whose visible mask covers it, kConflict where
/// instances of different classes do, kNoOwner where none does.
cv::Mat Owners(const cv::Mat& instance_ids, const std::vector<SegInstanceMask>& kept) {
  cv::Mat owner(instance_ids.size(), CV_32SC1, cv::Scalar(kNoOwner));
  for (size_t k = 0; k < kept.size(); ++k) {
    const SegInstanceMask& m = kept[k];
    MOCAP_CHECK(m.visible && m.visible->size() == static_cast<size_t>(std::max(0, m.rect.width * m.rect.height)), "mask size");
    for (int v = std::max(0, m.rect.y); v < std::min(owner.rows, m.rect.y + m.rect.height); ++v)
      for (int u = std::max(0, m.rect.x); u < std::min(owner.cols, m.rect.x + m.rect.width); ++u) {
        if (!Covers(m, u, v)) continue;
        int& o = owner.at<int>(v, u);
        if (o == kNoOwner) o = static_cast<int>(k);
        else if (o >= 0 && kept[static_cast<size_t>(o)].class_id != m.class_id) o = kConflict;
      }
  }
  return owner;
}

cv::Mat ReadInstanceIds(const ExportScene& scene, const ExportFrame& frame) {
  const fs::path png = scene.labels.InstancePng(scene.camera, frame.index);
  cv::Mat ids = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
  if (ids.empty()) throw InputError(png.string(), "missing or not a readable PNG (the label run's instance ids)");
  if (ids.type() != CV_16UC1 || ids.cols != scene.color_camera.width || ids.rows != scene.color_camera.height)
    throw InputError(png.string(), Str("expected a 16-bit ", scene.color_camera.width, "x", scene.color_camera.height,
                                       " instance image, got ", ids.cols, "x", ids.rows, " of OpenCV type ", ids.type()));
  return ids;
}

/// One frame's pair: the colour file placed, the class image built and written.
PairPaths WriteFrame(const Dataset& dataset, const ExportFrame& frame, const fs::path& dir,
                     const std::map<int, int>& class_of_object, int ignore_value, const SegPairsOptions& options) {
  if (frame.color_path.empty()) return {};
  const ExportScene& scene = dataset.scene_of(frame);
  char stem[48];
  std::snprintf(stem, sizeof stem, "%06d_%06d", scene.scene_id, frame.im_id);
  const PairPaths paths{Str(frame.split, "/", stem, LowerExtension(frame.color_path)), Str(frame.split, "annot/", stem, ".png")};
  const cv::Mat instance_ids = ReadInstanceIds(scene, frame);
  const std::vector<ObjectMasks> masks = ReadFrameMasks(scene, frame);
  std::vector<SegInstanceMask> kept;
  for (size_t i = 0; i < frame.instances.size(); ++i) {
    const pipeline::LabelRecord& r = frame.instances[i].record;
    const auto cls = class_of_object.find(r.object);
    MOCAP_CHECK(cls != class_of_object.end(), "object ", r.object, " is not in the dataset's object library");
    kept.push_back({cls->second, static_cast<uint16_t>(r.instance), masks[i].rect, &VisibleMask(masks[i], r)});
    if (masks[i].rect.empty()) kept.back().rect = {};  // covers no pixel: its masks are empty
  }
  WriteLabelPng(dir / paths.label, SegClassImage(instance_ids, kept, ignore_value, options.ignore_left_out));
  LinkOrCopyFile(frame.color_path, dir / paths.image);
  return paths;
}

std::string ClassesText(const std::vector<SegClass>& classes, const pipeline::ObjectLibrary& library, int ignore_value) {
  std::string text =
      "# segmentation classes of a mocaplabel export: id name r g b (colours: the PASCAL VOC colour map)\n"
      "# 0 = background; " + std::to_string(ignore_value) +
      " = ignore (objects the export's filters left out; overlaps nothing resolves)\n";
  for (const SegClass& c : classes) {
    text += Str("# class ", c.id, " '", FieldSafe(c.name), "': objects");
    for (int id : c.object_ids) text += Str(" ", id, " (", FieldSafe(library.FindId(id)->name), ")");
    text += "\n";
  }
  text += "0 background 0 0 0\n";
  for (const SegClass& c : classes) text += Str(c.id, " ", FieldSafe(c.name), " ", +c.rgb[0], " ", +c.rgb[1], " ", +c.rgb[2], "\n");
  return text + Str(ignore_value, " ignore ", +kIgnoreRgb[0], " ", +kIgnoreRgb[1], " ", +kIgnoreRgb[2], "\n");
}

}  // namespace

void SegPairsOptions::check() const {
  if (threads < 0) throw InputError("SegPairsOptions", "threads must be >= 0");
}

std::array<uint8_t, 3> SegClassColourRgb(int id) {
  std::array<uint8_t, 3> rgb{};
  int c = id;
  for (int j = 0; j < 8; ++j, c >>= 3)
    for (int channel = 0; channel < 3; ++channel) rgb[channel] |= static_cast<uint8_t>(((c >> channel) & 1) << (7 - j));
  return rgb;
}

std::vector<SegClass> SegClasses(const pipeline::ObjectLibrary& library) {
  std::map<std::string, std::vector<int>> ids_of_class;
  for (const pipeline::LibraryObject& o : library.objects) ids_of_class[o.object_class].push_back(o.id);
  std::vector<SegClass> classes;
  for (auto& [name, ids] : ids_of_class) {
    std::sort(ids.begin(), ids.end());
    classes.push_back({0, name, {}, ids});
  }
  std::sort(classes.begin(), classes.end(), [](const SegClass& a, const SegClass& b) { return a.object_ids[0] < b.object_ids[0]; });
  for (size_t i = 0; i < classes.size(); ++i) {
    classes[i].id = static_cast<int>(i + 1);
    classes[i].rgb = SegClassColourRgb(classes[i].id);
  }
  return classes;
}

cv::Mat SegClassImage(const cv::Mat& instance_ids, const std::vector<SegInstanceMask>& kept, int ignore_value, bool ignore_left_out) {
  MOCAP_CHECK(instance_ids.type() == CV_16UC1, "instance ids must be CV_16UC1");
  MOCAP_CHECK(ignore_value == 255 || ignore_value == 65535, "ignore value ", ignore_value);
  std::vector<int> kept_of_instance(65536, -1);
  for (size_t k = 0; k < kept.size(); ++k) kept_of_instance[kept[k].instance_id] = static_cast<int>(k);
  const cv::Mat owner = Owners(instance_ids, kept);
  cv::Mat classes(instance_ids.size(), CV_16UC1);
  for (int v = 0; v < classes.rows; ++v)
    for (int u = 0; u < classes.cols; ++u) {
      const int o = owner.at<int>(v, u);
      const uint16_t front = instance_ids.at<uint16_t>(v, u);  // the model z-buffer's nearest instance
      int value = 0;
      if (o >= 0) {
        value = kept[static_cast<size_t>(o)].class_id;
      } else if (o == kConflict) {
        const int k = kept_of_instance[front];
        value = k >= 0 && Covers(kept[static_cast<size_t>(k)], u, v) ? kept[static_cast<size_t>(k)].class_id : ignore_value;
      } else if (front != 0 && kept_of_instance[front] < 0 && ignore_left_out) {
        value = ignore_value;
      }
      classes.at<uint16_t>(v, u) = static_cast<uint16_t>(value);
    }
  if (ignore_value == 65535) return classes;
  cv::Mat classes8;
  classes.convertTo(classes8, CV_8UC1);
  return classes8;
}

WriteSummary WriteSegPairs(const Dataset& dataset, const fs::path& dir, const SegPairsOptions& options) {
  options.check();
  WriteSummary summary;
  summary.format = "segpairs";
  const std::vector<SegClass> classes = SegClasses(dataset.objects);
  const int ignore_value = classes.size() < 255 ? 255 : 65535;  // ids 1..254 fit 8 bits beside 255
  std::map<int, int> class_of_object;
  for (const SegClass& c : classes)
    for (int id : c.object_ids) class_of_object[id] = c.id;
  for (const std::string& split : dataset.splits())
    for (const std::string& sub : {split, split + "annot"}) fs::create_directories(dir / sub);
  std::vector<PairPaths> pairs(dataset.frames.size());
  const int threads = WorkerThreads(options.threads);
  ParallelFor(dataset.frames.size(), threads, [&](size_t i) {
    pairs[i] = WriteFrame(dataset, dataset.frames[i], dir, class_of_object, ignore_value, options);
  });
  std::map<std::string, std::string> lists = {{"train", ""}, {"val", ""}, {"test", ""}};
  int64_t without_colour = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    const ExportFrame& f = dataset.frames[i];
    if (pairs[i].image.empty()) {
      ++without_colour;
      continue;
    }
    lists[f.split] += pairs[i].image + " " + pairs[i].label + "\n";
    ++summary.images, ++summary.images_per_split[f.split];
    summary.annotations += static_cast<int64_t>(f.instances.size());
    summary.annotations_per_split[f.split] += static_cast<int64_t>(f.instances.size());
  }
  WriteFileAtomically(dir / "classes.txt", ClassesText(classes, dataset.objects, ignore_value));
  for (const auto& [split, text] : lists) WriteFileAtomically(dir / (split + ".txt"), text);
  summary.files = 2 * summary.images + 1 + static_cast<int64_t>(lists.size());
  if (without_colour > 0) summary.notes.push_back(Str(without_colour, " frames without a colour image left out"));
  if (ignore_value == 65535) summary.notes.push_back("more than 254 classes: 16-bit label images, ignore value 65535");
  return summary;
}

}  // namespace mocap::exporters
