#include "exporters/dataset/dataset.h"

#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "label/mask_file.h"

namespace mocap::exporters {
namespace fs = std::filesystem;

std::vector<std::string> Dataset::splits() const {
  std::vector<std::string> out;
  for (const char* name : {"train", "val", "test"})
    for (const ExportFrame& f : frames)
      if (f.split == name) {
        out.push_back(name);
        break;
      }
  return out;
}

std::vector<ObjectMasks> ReadFrameMasks(const ExportScene& scene, const ExportFrame& frame) {
  std::vector<ObjectMasks> masks(frame.instances.size());
  const fs::path png = scene.labels.MaskBitsPng(scene.camera, frame.index);
  cv::Mat file;  // read once, when the first instance with pixels needs it
  for (size_t i = 0; i < frame.instances.size(); ++i) {
    const pipeline::LabelRecord& r = frame.instances[i].record;
    masks[i].instance_id = static_cast<uint16_t>(r.instance);
    if (!r.has_mask_fields)
      throw InputError(scene.labels.labels_jsonl().string(),
                       Str("frame ", frame.index, " instance ", r.instance, " of camera ", scene.camera,
                           ": the label run wrote no masks (labelled with --no-masks); label the session again without it"));
    if (!r.mask_rect || !r.mask_row) continue;  // covers no pixel of the image
    const auto& b = *r.mask_rect;
    const PixelRect rect{b[0], b[1], b[2], b[3]};
    if (file.empty()) {
      file = cv::imread(png.string(), cv::IMREAD_UNCHANGED);
      if (file.empty()) throw InputError(png.string(), "missing or not a readable PNG (the label run's packed masks)");
    }
    masks[i] = MasksFromFile(file, png.string(), rect, r.visib_source == "measured_depth", *r.mask_row);
    masks[i].instance_id = static_cast<uint16_t>(r.instance);
  }
  return masks;
}

const std::vector<uint8_t>& VisibleMask(const ObjectMasks& masks, const pipeline::LabelRecord& record) {
  return record.visib_source == "measured_depth" ? masks.visible_measured : masks.visible_model;
}

}  // namespace mocap::exporters
