// The live page's thumbnails: a downscaled JPEG of the colour frame and a PNG of its labels drawn in the
// instances' colours over transparency, which the page lays over the JPEG. Kept apart (rather than
// drawn into the JPEG) so the labels stay exact: JPEG would smear their colours and edges.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>

#include "capture/daemon/live_view.h"
#include "core/check.h"

namespace mocap::capture {

namespace {

constexpr uint8_t kFillAlpha = 110;     // the frame shows through the labels
constexpr uint8_t kOutlineAlpha = 255;  // an instance's edge stays visible on any background

cv::Vec3b InstanceBgr(uint16_t id) {
  // Hues by the golden angle: neighbouring ids get far-apart colours; full saturation and value so the
  // colours stay distinct from each other (and exact in the lossless PNG).
  const double hue = std::fmod(static_cast<double>(id) * 137.50776405, 360.0);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue / 2.0, 255, 255)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  return bgr.at<cv::Vec3b>(0, 0);
}

std::string Encode(const std::string& ext, const cv::Mat& image, const std::vector<int>& params) {
  std::vector<uint8_t> bytes;
  if (!cv::imencode(ext, image, bytes, params)) throw InputError("live thumbnail", "cannot encode " + ext);
  return {bytes.begin(), bytes.end()};
}

bool OnEdge(const cv::Mat& ids, int r, int c) {
  const uint16_t id = ids.at<uint16_t>(r, c);
  return (r == 0 || ids.at<uint16_t>(r - 1, c) != id) || (r + 1 == ids.rows || ids.at<uint16_t>(r + 1, c) != id) ||
         (c == 0 || ids.at<uint16_t>(r, c - 1) != id) || (c + 1 == ids.cols || ids.at<uint16_t>(r, c + 1) != id);
}

// BGRA: each instance's colour, half transparent inside and opaque on its edge; background transparent.
cv::Mat LabelsImage(const cv::Mat& ids) {
  cv::Mat out(ids.size(), CV_8UC4, cv::Scalar(0, 0, 0, 0));
  std::map<uint16_t, cv::Vec3b> colors;
  for (int r = 0; r < ids.rows; ++r) {
    for (int c = 0; c < ids.cols; ++c) {
      const uint16_t id = ids.at<uint16_t>(r, c);
      if (id == 0) continue;
      auto found = colors.find(id);
      if (found == colors.end()) found = colors.emplace(id, InstanceBgr(id)).first;
      const cv::Vec3b& bgr = found->second;
      out.at<cv::Vec4b>(r, c) = {bgr[0], bgr[1], bgr[2], OnEdge(ids, r, c) ? kOutlineAlpha : kFillAlpha};
    }
  }
  return out;
}

}  // namespace

std::string InstanceColor(uint16_t id) {
  const cv::Vec3b bgr = InstanceBgr(id);
  char text[8];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", bgr[2], bgr[1], bgr[0]);
  return text;
}

Thumbnail EncodeThumbnail(const cv::Mat& color_bgr, const FrameLabels* labels, int width_px, int jpeg_quality) {
  MOCAP_CHECK(color_bgr.type() == CV_8UC3 && !color_bgr.empty(), "thumbnail of a non-BGR image");
  Thumbnail t;
  t.width = std::min(width_px, color_bgr.cols);
  t.height = std::max(1, static_cast<int>(std::lround(static_cast<double>(color_bgr.rows) * t.width / color_bgr.cols)));
  cv::Mat small;
  cv::resize(color_bgr, small, {t.width, t.height}, 0, 0, cv::INTER_AREA);
  t.jpeg = Encode(".jpg", small, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality});
  if (!labels) return t;
  if (labels->instance_ids.type() != CV_16UC1 || labels->instance_ids.size() != color_bgr.size())
    throw InputError("live labels", Str("instance image of ", labels->instance_ids.cols, "x", labels->instance_ids.rows,
                                        " does not match the colour image's ", color_bgr.cols, "x", color_bgr.rows));
  cv::Mat ids;
  cv::resize(labels->instance_ids, ids, {t.width, t.height}, 0, 0, cv::INTER_NEAREST);
  t.labels_png = Encode(".png", LabelsImage(ids), {cv::IMWRITE_PNG_COMPRESSION, 3});
  for (const FrameLabels::Instance& i : labels->instances)
    t.legend.push_back({{"id", i.id}, {"object", i.object}, {"body", i.body}, {"color", InstanceColor(i.id)},
                        {"drawn", i.drawn}, {"reason", i.reason}});
  return t;
}

}  // namespace mocap::capture
