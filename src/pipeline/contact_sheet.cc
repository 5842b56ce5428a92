#include "pipeline/contact_sheet.h"

#include <algorithm>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/check.h"
#include "pipeline/label_run.h"
#include "session/image_io.h"
#include "session/reader.h"

namespace mocap::pipeline {
namespace {

cv::Vec3b InstanceColor(int id) {  // BGR, well separated for small ids
  static const cv::Vec3b palette[] = {{60, 76, 231}, {113, 204, 46}, {219, 152, 52}, {15, 196, 241},
                                      {182, 89, 155}, {34, 126, 230}, {160, 160, 22}, {96, 174, 39}};
  return palette[static_cast<size_t>(id) % (sizeof palette / sizeof palette[0])];
}

cv::Mat Overlay(const cv::Mat& bgr, const LabelImage& ids, double alpha) {
  cv::Mat out = bgr.clone();
  for (int v = 0; v < ids.height; ++v)
    for (int u = 0; u < ids.width; ++u) {
      const uint16_t id = ids.at(u, v);
      if (id == 0) continue;
      const bool edge = (u > 0 && ids.at(u - 1, v) != id) || (v > 0 && ids.at(u, v - 1) != id) ||
                        (u + 1 < ids.width && ids.at(u + 1, v) != id) || (v + 1 < ids.height && ids.at(u, v + 1) != id);
      const cv::Vec3b c = InstanceColor(id);
      cv::Vec3b& p = out.at<cv::Vec3b>(v, u);
      const double a = edge ? 1.0 : alpha;
      for (int k = 0; k < 3; ++k) p[k] = cv::saturate_cast<uint8_t>((1 - a) * p[k] + a * c[k]);
    }
  return out;
}

}  // namespace

void ContactSheetOptions::check() const {
  if (columns < 1 || rows < 1 || columns * rows > 64) throw InputError("contact sheet", "columns x rows must be 1..64");
  if (cell_width_px < 16 || cell_width_px > 4096) throw InputError("contact sheet", "cell_width_px must be 16..4096");
  if (!(alpha >= 0 && alpha <= 1)) throw InputError("contact sheet", "alpha must be in [0, 1]");
}

void WriteContactSheet(const SessionReader& session, const std::string& camera, const std::filesystem::path& labels_dir,
                       const std::filesystem::path& out_png, const ContactSheetOptions& options) {
  options.check();
  const int64_t frames = session.frame_count(camera);
  if (frames <= 0) throw InputError(session.dir().string(), "no frames of camera '" + camera + "' for a contact sheet");
  const int cells = static_cast<int>(std::min<int64_t>(frames, options.columns * options.rows));
  cv::Mat sheet;
  for (int c = 0; c < cells; ++c) {
    const int64_t index = cells == 1 ? 0 : c * (frames - 1) / (cells - 1);
    const cv::Mat bgr = session.LoadColor(camera, index);
    const std::filesystem::path ids_path = LabelRunLayout{labels_dir}.InstancePng(camera, index);
    const LabelImage ids = ReadIdImage(ids_path);
    if (bgr.empty() || ids.width != bgr.cols || ids.height != bgr.rows)
      throw InputError(ids_path.string(), "missing colour frame, or a label image of another size, for the contact sheet");
    cv::Mat cell;
    const double scale = double(options.cell_width_px) / bgr.cols;
    cv::resize(Overlay(bgr, ids, options.alpha), cell, cv::Size(), scale, scale, cv::INTER_AREA);
    cv::putText(cell, "frame " + std::to_string(index), {6, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {255, 255, 255}, 1, cv::LINE_AA);
    const int rows = (cells + options.columns - 1) / options.columns;
    if (sheet.empty()) sheet = cv::Mat(cell.rows * rows, cell.cols * options.columns, CV_8UC3, cv::Scalar(0, 0, 0));
    cell.copyTo(sheet(cv::Rect((c % options.columns) * cell.cols, (c / options.columns) * cell.rows, cell.cols, cell.rows)));
  }
  if (!cv::imwrite(out_png.string(), sheet)) throw InputError(out_png.string(), "could not write the contact sheet");
}

}  // namespace mocap::pipeline
