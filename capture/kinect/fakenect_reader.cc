// Reading side of fakenect_recording.h: what the fakenect replay library would read, for checks and tools.
#include <cstdio>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "core/check.h"
#include "capture/kinect/fakenect_recording.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

// Whole file, then the one-line PNM header fakenect skips; checks the header names the size we expect.
std::vector<char> ReadPnm(const fs::path& file, const std::string& expected_header, size_t payload_bytes) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "cannot be opened");
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string header(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(
                                                             std::min(bytes.size(), expected_header.size())));
  if (header != expected_header)
    throw InputError(file.string() + ":1", Str("header is not '", expected_header.substr(0, expected_header.size() - 1),
                                               "' (fakenect replays only 640x480)"));
  if (bytes.size() != expected_header.size() + payload_bytes)
    throw InputError(file.string(), Str("holds ", bytes.size() - expected_header.size(), " bytes of pixels, expected ",
                                        payload_bytes));
  bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(expected_header.size()));
  return bytes;
}

}  // namespace

std::vector<FakenectEntry> ReadFakenectIndex(const fs::path& dir) {
  const fs::path index_path = dir / "INDEX.txt";
  std::ifstream in(index_path);
  if (!in) throw InputError(index_path.string(), "cannot be opened (not a fakenect recording?)");
  std::vector<FakenectEntry> entries;
  std::string line;
  for (int line_number = 1; std::getline(in, line); ++line_number) {
    const std::string where = Str(index_path.string(), ":", line_number);
    FakenectEntry entry;
    unsigned int ticks = 0;
    char extension[16] = {};
    // The same pattern fakenect.c parses with: "%c-%lf-%u-%*s", plus the extension after the dot.
    if (std::sscanf(line.c_str(), "%c-%lf-%u.%15s", &entry.type, &entry.host_time_s, &ticks, extension) != 4 ||
        (entry.type != 'd' && entry.type != 'r' && entry.type != 'a'))
      throw InputError(where, "expected '<d|r|a>-<host seconds>-<device ticks>.<ext>', got '" + line + "'");
    entry.ticks = ticks;
    entry.file = dir / line;
    if (!fs::exists(entry.file)) throw InputError(where, "names a file that does not exist: " + line);
    entries.push_back(std::move(entry));
  }
  return entries;
}

cv::Mat ReadFakenectDepthRaw(const fs::path& file) {
  const size_t pixels = size_t{kFakenectWidth} * kFakenectHeight;
  const std::vector<char> bytes = ReadPnm(file, "P5 640 480 65535\n", pixels * 2);
  cv::Mat raw(kFakenectHeight, kFakenectWidth, CV_16UC1);
  auto* out = raw.ptr<uint16_t>();
  for (size_t i = 0; i < pixels; ++i)
    out[i] = static_cast<uint16_t>(static_cast<uint8_t>(bytes[2 * i]) | (static_cast<uint8_t>(bytes[2 * i + 1]) << 8));
  return raw;
}

cv::Mat ReadFakenectColorBgr(const fs::path& file) {
  const size_t pixels = size_t{kFakenectWidth} * kFakenectHeight;
  std::vector<char> bytes = ReadPnm(file, "P6 640 480 255\n", pixels * 3);
  cv::Mat rgb(kFakenectHeight, kFakenectWidth, CV_8UC3, bytes.data());
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  return bgr;
}

std::optional<RecordingCamera> ReadRecordingCamera(const fs::path& dir) {
  const fs::path path = dir / kRecordingCameraFile;
  if (!fs::exists(path)) return std::nullopt;
  std::ifstream in(path);
  try {
    const nlohmann::json doc = nlohmann::json::parse(in);
    const auto& c = doc.at("depth_camera");
    RecordingCamera camera;
    camera.depth_camera = {c.at("width").get<int>(), c.at("height").get<int>(), c.at("fx").get<double>(),
                           c.at("fy").get<double>(), c.at("cx").get<double>(), c.at("cy").get<double>(),
                           c.at("dist").get<std::array<double, 8>>()};
    camera.depth_registered = doc.at("depth_registered").get<bool>();
    camera.depth_camera.check();
    return camera;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string(), std::string("malformed: ") + e.what());
  }
}

}  // namespace mocap::capture
