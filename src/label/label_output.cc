#include "label/label_output.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/check.h"

namespace mocap {
namespace {

cv::Scalar Colour(uint16_t instance_id) {
  // Well-separated hues by the golden angle, full saturation (BGR).
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar((instance_id * 137) % 180, 220, 255)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return {static_cast<double>(c[0]), static_cast<double>(c[1]), static_cast<double>(c[2])};
}

cv::Mat OverlayImpl(const cv::Mat& color, const RenderOutput& render, const std::vector<InstanceResult>& results) {
  cv::Mat out = color.clone();
  for (int v = 0; v < out.rows; ++v) {
    for (int u = 0; u < out.cols; ++u) {
      const uint16_t id = render.instance_ids.at(u, v);
      if (id == 0) continue;
      const cv::Scalar c = Colour(id);
      cv::Vec3b& px = out.at<cv::Vec3b>(v, u);
      for (int k = 0; k < 3; ++k) px[k] = static_cast<uint8_t>(0.45 * px[k] + 0.55 * c[k]);
    }
  }
  for (const InstanceResult& r : results) {
    if (r.labels == nullptr || r.labels->stats.bbox_visib[0] < 0) continue;
    const auto& b = r.labels->stats.bbox_visib;
    const cv::Scalar c = Colour(r.instance->instance_id);
    cv::rectangle(out, cv::Rect(b[0], b[1], b[2] + 1, b[3] + 1), c, 1);
    cv::putText(out, r.instance->object->name, {b[0], std::max(b[1] - 3, 10)}, cv::FONT_HERSHEY_SIMPLEX, 0.4, c, 1);
  }
  return out;
}

}  // namespace

/// Object ids per pixel, through a lookup from instance id, into a buffer of the calling thread that the
/// next call overwrites (no fresh pages to fault in per frame). Only the objects' rectangles are looked
/// up: no instance id lies outside them.
const LabelImage& ClassImage(const RenderOutput& render, const std::vector<InstanceResult>& results) {
  std::vector<uint16_t> class_of(1, 0);
  for (const InstanceResult& r : results) {
    const uint16_t id = r.instance->instance_id;
    if (class_of.size() <= id) class_of.resize(id + 1u, 0);
    class_of[id] = static_cast<uint16_t>(r.instance->object->id);
  }
  const LabelImage& ids = render.instance_ids;
  thread_local LabelImage classes;
  classes.width = ids.width, classes.height = ids.height;
  classes.data.assign(ids.data.size(), 0);
  for (const ObjectLayer& layer : render.layers) {
    const PixelRect& r = layer.rect;
    for (int v = r.y; v < r.y + r.height; ++v)
      for (int u = r.x; u < r.x + r.width; ++u) {
        const uint16_t id = ids.at(u, v);
        classes.at(u, v) = id < class_of.size() ? class_of[id] : 0;
      }
  }
  return classes;
}

cv::Mat OverlayImage(const cv::Mat& color, const RenderOutput& render, const std::vector<InstanceResult>& results) {
  return OverlayImpl(color, render, results);
}

cv::Mat FullMaskImage(const std::vector<uint8_t>& mask, const PixelRect& rect, int width, int height) {
  const Image<uint8_t> full = ToFullImage(mask, rect, width, height);
  return cv::Mat(height, width, CV_8UC1, const_cast<uint8_t*>(full.data.data())).clone();
}

}  // namespace mocap
