#include "capture/kinect/fakenect_recording.h"

#include <libfreenect.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "core/check.h"
#include "core/log.h"
#include "capture/kinect/kinect1_depth.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

std::string FrameWhere(const fs::path& dir, int frame) { return Str(dir.string(), " frame ", frame); }

double DepthAtM(const cv::Mat& depth, int row, int col) {
  switch (depth.type()) {
    case CV_16UC1: return depth.at<uint16_t>(row, col) * 1e-3;
    case CV_32FC1: return depth.at<float>(row, col);
    default: return depth.at<double>(row, col);
  }
}

// Raw disparity as fakenect stores it: little-endian uint16 regardless of the host.
std::vector<uint8_t> DepthToRawBytes(const cv::Mat& depth, FakenectFrameStats& stats) {
  std::vector<uint8_t> bytes(static_cast<size_t>(depth.total()) * 2);
  size_t i = 0;
  for (int row = 0; row < depth.rows; ++row) {
    for (int col = 0; col < depth.cols; ++col, i += 2) {
      const double depth_m = DepthAtM(depth, row, col);
      uint16_t raw = kKinect1RawNoValue;
      if (!(depth_m > 0.0)) {
        ++stats.depth_no_value;
      } else if ((raw = DepthMToRaw11(depth_m)) == kKinect1RawNoValue) {
        ++stats.depth_unrepresentable;
      } else {
        ++stats.depth_valid;
      }
      bytes[i] = static_cast<uint8_t>(raw & 0xff);
      bytes[i + 1] = static_cast<uint8_t>(raw >> 8);
    }
  }
  return bytes;
}

void CheckFrame(const cv::Mat& bgr, const cv::Mat& depth, const std::string& where) {
  if (bgr.type() != CV_8UC3 || bgr.cols != kFakenectWidth || bgr.rows != kFakenectHeight)
    throw InputError(where, Str("colour must be CV_8UC3 640x480, got type ", bgr.type(), " ", bgr.cols, "x",
                                bgr.rows, " (fakenect 0.5.3 replays only 640x480 RGB)"));
  const int type = depth.type();
  if ((type != CV_16UC1 && type != CV_32FC1 && type != CV_64FC1) || depth.cols != kFakenectWidth ||
      depth.rows != kFakenectHeight)
    throw InputError(where, Str("depth must be 640x480 CV_16UC1 (mm) or CV_32FC1/CV_64FC1 (m), got type ", type,
                                " ", depth.cols, "x", depth.rows));
}

freenect_raw_tilt_state ToRawTilt(const TiltSample& tilt) {
  freenect_raw_tilt_state state{};
  state.accelerometer_x = tilt.accel_raw[0];
  state.accelerometer_y = tilt.accel_raw[1];
  state.accelerometer_z = tilt.accel_raw[2];
  // libfreenect's encoder counts half degrees (freenect_get_tilt_degs divides by 2).
  state.tilt_angle = static_cast<int8_t>(std::lround(tilt.tilt_deg * 2.0));
  state.tilt_status = static_cast<freenect_tilt_status_code>(tilt.tilt_status);
  return state;
}

}  // namespace

FakenectRecordingWriter::FakenectRecordingWriter(const fs::path& dir, std::optional<RecordingCamera> camera)
    : dir_(dir), camera_(std::move(camera)) {
  std::error_code error;
  fs::create_directories(dir_, error);
  if (error) throw InputError(dir_.string(), "cannot create the recording directory: " + error.message());
  if (fs::exists(dir_ / "INDEX.txt"))
    throw InputError((dir_ / "INDEX.txt").string(), "a recording is already there; choose an empty directory");
  if (camera_) camera_->depth_camera.check();
  index_.open(dir_ / "INDEX.txt");
  if (!index_) throw InputError((dir_ / "INDEX.txt").string(), "cannot be written");
}

FakenectRecordingWriter::~FakenectRecordingWriter() {
  try {
    Close();
  } catch (const std::exception& e) {
    Log().error("fakenect recording {}: {}", dir_.string(), e.what());
  }
}

std::string FakenectRecordingWriter::WriteFile(char type, double host_time_s, uint32_t ticks,
                                               const std::string& extension, const std::string& header,
                                               const void* data, size_t bytes) {
  char name[96];
  std::snprintf(name, sizeof(name), "%c-%.6f-%u.%s", type, host_time_s, ticks, extension.c_str());
  const fs::path path = dir_ / name;
  if (fs::exists(path))
    throw InputError(path.string(), "two frames share host time and device ticks; replay needs distinct names");
  std::ofstream out(path, std::ios::binary);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  if (!out) throw InputError(path.string(), "cannot be written (disk full?)");
  index_ << name << '\n';
  return name;
}

FakenectFrameStats FakenectRecordingWriter::AddFrame(const cv::Mat& bgr, const cv::Mat& depth,
                                                     uint64_t device_ticks, double host_time_s,
                                                     const std::optional<TiltSample>& tilt) {
  const std::string where = FrameWhere(dir_, frames_);
  MOCAP_CHECK(index_.is_open(), "AddFrame after Close on ", dir_.string());
  CheckFrame(bgr, depth, where);
  if (!std::isfinite(host_time_s) || host_time_s < last_host_time_s_)
    throw InputError(where, Str("host time ", host_time_s, " s is before the previous frame's ", last_host_time_s_,
                                " s; replay needs non-decreasing host times"));
  const auto ticks = static_cast<uint32_t>(device_ticks & 0xffffffffu);
  if (tilt) {
    const freenect_raw_tilt_state state = ToRawTilt(*tilt);
    WriteFile('a', host_time_s, ticks, "dump", "", &state, sizeof(state));
  }
  FakenectFrameStats stats;
  const std::vector<uint8_t> raw = DepthToRawBytes(depth, stats);
  WriteFile('d', host_time_s, ticks, "pgm", "P5 640 480 65535\n", raw.data(), raw.size());
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  if (!rgb.isContinuous()) rgb = rgb.clone();
  WriteFile('r', host_time_s, ticks, "ppm", "P6 640 480 255\n", rgb.data, rgb.total() * 3);
  if (!index_) throw InputError((dir_ / "INDEX.txt").string(), "cannot be written (disk full?)");
  totals_.depth_valid += stats.depth_valid;
  totals_.depth_no_value += stats.depth_no_value;
  totals_.depth_unrepresentable += stats.depth_unrepresentable;
  last_host_time_s_ = host_time_s;
  ++frames_;
  return stats;
}

void FakenectRecordingWriter::Close() {
  if (!index_.is_open()) return;
  index_.close();
  if (!index_) throw InputError((dir_ / "INDEX.txt").string(), "cannot be written (disk full?)");
  if (!camera_) return;
  const PinholeCamera& c = camera_->depth_camera;
  const nlohmann::json doc = {
      {"depth_camera",
       {{"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy},
        {"dist", c.dist}}},
      {"depth_registered", camera_->depth_registered},
      {"depth_encoding", "raw 11-bit disparity, z[m] = 1/(-0.0030711 raw + 3.3309495)"}};
  std::ofstream out(dir_ / kRecordingCameraFile);
  out << doc.dump(2) << '\n';
  if (!out) throw InputError((dir_ / kRecordingCameraFile).string(), "cannot be written");
}

}  // namespace mocap::capture
