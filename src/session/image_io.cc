#include "session/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <Iex.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "session/durable_file.h"
#include "session/png_gray16.h"
#include "session/png_write.h"

namespace mocap {
namespace fs = std::filesystem;

namespace {

std::vector<uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw InputError(path.string(), fs::exists(path) ? "cannot open the image" : "image file is missing");
  std::vector<uint8_t> bytes(static_cast<size_t>(in.tellg()));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size())))
    throw InputError(path.string(), "cannot read the image");
  return bytes;
}

bool EndsWith(const std::vector<uint8_t>& bytes, std::initializer_list<uint8_t> tail) {
  return bytes.size() >= tail.size() && std::equal(tail.begin(), tail.end(), bytes.end() - tail.size());
}

bool StartsWith(const std::vector<uint8_t>& bytes, std::initializer_list<uint8_t> head) {
  return bytes.size() >= head.size() && std::equal(head.begin(), head.end(), bytes.begin());
}

/// Refuses a PNG without its IEND chunk or a JPEG without its EOI marker: decoders would otherwise
/// return the part that was read (libjpeg fills the rest grey with only a warning).
void CheckWhole(const std::vector<uint8_t>& bytes, const fs::path& path) {
  if (StartsWith(bytes, {0x89, 'P', 'N', 'G'})) {
    if (!EndsWith(bytes, {'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82}))
      throw InputError(path.string(), Str("PNG is truncated or corrupt (no IEND chunk at its end; ", bytes.size(),
                                          " bytes)"));
  } else if (StartsWith(bytes, {0xFF, 0xD8})) {
    if (!EndsWith(bytes, {0xFF, 0xD9}))
      throw InputError(path.string(), Str("JPEG is truncated (no end-of-image marker; ", bytes.size(), " bytes)"));
  }
}

std::vector<uint8_t> ReadWholeImage(const fs::path& path) {
  std::vector<uint8_t> bytes = ReadBytes(path);
  if (bytes.empty()) throw InputError(path.string(), "image file is empty");
  CheckWhole(bytes, path);
  return bytes;
}

cv::Mat Decode(const fs::path& path, const std::vector<uint8_t>& bytes, int flags) {
  cv::Mat image;
  try {
    image = cv::imdecode(bytes, flags);
  } catch (const cv::Exception& e) {
    throw InputError(path.string(), Str("cannot decode the image: ", e.what()));
  }
  if (image.empty()) throw InputError(path.string(), "cannot decode the image (corrupt or not PNG/JPEG)");
  return image;
}

DepthImage ReadDepthExr(const fs::path& path) {
  if (!fs::exists(path)) throw InputError(path.string(), "image file is missing");
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    const int width = window.max.x - window.min.x + 1;
    const int height = window.max.y - window.min.y + 1;
    const Imf::ChannelList& channels = file.header().channels();
    const char* name = channels.findChannel("Z") ? "Z" : nullptr;
    if (!name) throw InputError(path.string(), "OpenEXR depth needs a channel named \"Z\" (metres)");
    DepthImage depth(width, height);
    Imf::FrameBuffer buffer;
    char* origin = reinterpret_cast<char*>(depth.data.data()) -
                   (static_cast<ptrdiff_t>(window.min.x) + static_cast<ptrdiff_t>(window.min.y) * width) * sizeof(float);
    buffer.insert(name, Imf::Slice(Imf::FLOAT, origin, sizeof(float), sizeof(float) * width));
    file.setFrameBuffer(buffer);
    file.readPixels(window.min.y, window.max.y);
    for (float& d : depth.data)
      if (!std::isfinite(d) || d < 0.0f) d = 0.0f;
    return depth;
  } catch (const Iex::BaseExc& e) {
    throw InputError(path.string(), Str("cannot read OpenEXR depth: ", e.what()));
  }
}

}  // namespace

bool IsWholeJpeg(const std::vector<uint8_t>& bytes) {
  return StartsWith(bytes, {0xFF, 0xD8, 0xFF}) && EndsWith(bytes, {0xFF, 0xD9});
}

std::vector<uint8_t> EncodeColor(const cv::Mat& color, const std::string& extension, int png_compression,
                                 int jpeg_quality) {
  MOCAP_CHECK(color.type() == CV_8UC3 || color.type() == CV_8UC1, "colour must be CV_8UC3 or CV_8UC1");
  std::vector<int> params;
  if (extension == ".png" && png_compression >= 0) params = {cv::IMWRITE_PNG_COMPRESSION, png_compression};
  if (extension == ".jpg") params = {cv::IMWRITE_JPEG_QUALITY, jpeg_quality};
  std::vector<uint8_t> bytes;
  MOCAP_CHECK(cv::imencode(extension, color, bytes, params), "encoding ", extension, " failed");
  return bytes;
}

std::vector<uint8_t> EncodeDepthPng(const cv::Mat& depth, double depth_unit_m, int png_compression) {
  MOCAP_CHECK(depth.type() == CV_16UC1 || depth.type() == CV_32FC1, "depth must be CV_16UC1 or CV_32FC1");
  cv::Mat units = depth;
  if (depth.type() == CV_32FC1) {
    units.create(depth.size(), CV_16UC1);
    for (int v = 0; v < depth.rows; ++v) {
      const float* in = depth.ptr<float>(v);
      uint16_t* out = units.ptr<uint16_t>(v);
      for (int u = 0; u < depth.cols; ++u) {
        const double value = std::round(static_cast<double>(in[u]) / depth_unit_m);
        out[u] = (value > 0.0 && value <= 65535.0) ? static_cast<uint16_t>(value) : 0;
      }
    }
  }
  return EncodeGray16Png(units, png_compression < 0 ? kDefaultDepthPngLevel : png_compression);
}

void WriteDepthExr(const fs::path& path, const cv::Mat& depth, double depth_unit_m) {
  MOCAP_CHECK(depth.type() == CV_16UC1 || depth.type() == CV_32FC1, "depth must be CV_16UC1 or CV_32FC1");
  cv::Mat metres;
  if (depth.type() == CV_16UC1) {
    depth.convertTo(metres, CV_32FC1, depth_unit_m);
  } else {
    metres = depth.isContinuous() ? depth : depth.clone();
  }
  try {
    Imf::Header header(metres.cols, metres.rows);
    header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    header.compression() = Imf::ZIPS_COMPRESSION;
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer buffer;
    buffer.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(metres.ptr<float>(0)), sizeof(float),
                                  sizeof(float) * metres.cols));
    file.setFrameBuffer(buffer);
    file.writePixels(metres.rows);
  } catch (const Iex::BaseExc& e) {
    std::error_code ignored;
    fs::remove(path, ignored);
    throw InputError(path.string(), Str("cannot write OpenEXR depth: ", e.what()));
  }
}

cv::Mat ReadColor(const fs::path& path) {
  cv::Mat image = Decode(path, ReadWholeImage(path), cv::IMREAD_COLOR);
  MOCAP_CHECK(image.type() == CV_8UC3, "IMREAD_COLOR gave type ", image.type());
  return image;
}

DepthImage ReadDepth(const fs::path& path, double depth_unit_m) {
  if (path.extension() == ".exr") return ReadDepthExr(path);
  const std::vector<uint8_t> bytes = ReadWholeImage(path);
  // The common case, 16-bit greyscale PNG, takes the fast decoder; any other kind goes to OpenCV.
  if (std::optional<DepthImage> depth = DecodeGray16Png(bytes, depth_unit_m, path.string())) return std::move(*depth);
  const cv::Mat raw = Decode(path, bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
  if (raw.type() != CV_16UC1)
    throw InputError(path.string(), "depth PNG must be 16-bit single-channel (this one is 8-bit or colour)");
  DepthImage depth(raw.cols, raw.rows);
  for (int v = 0; v < raw.rows; ++v) {
    const uint16_t* in = raw.ptr<uint16_t>(v);
    for (int u = 0; u < raw.cols; ++u) depth.at(u, v) = static_cast<float>(in[u] * depth_unit_m);
  }
  return depth;
}

LabelImage ReadIdImage(const fs::path& path) {
  if (!fs::exists(path)) throw InputError(path.string(), "id image is missing");
  const std::vector<uint8_t> bytes = ReadWholeImage(path);
  // A label run writes 16-bit ids: the depth decoder reads them (its float holds every 16-bit id exactly).
  if (const std::optional<Image<float>> ids = DecodeGray16Png(bytes, 1.0, path.string())) {
    LabelImage out(ids->width, ids->height);
    std::transform(ids->data.begin(), ids->data.end(), out.data.begin(), [](float id) { return static_cast<uint16_t>(id); });
    return out;
  }
  const cv::Mat m = Decode(path, bytes, cv::IMREAD_UNCHANGED);
  if (m.channels() != 1 || (m.depth() != CV_8U && m.depth() != CV_16U))
    throw InputError(path.string(), "must be a single-channel 8- or 16-bit PNG of ids (0 = background)");
  cv::Mat ids;
  m.convertTo(ids, CV_16U);
  LabelImage out(ids.cols, ids.rows);
  for (int v = 0; v < ids.rows; ++v) std::copy_n(ids.ptr<uint16_t>(v), ids.cols, &out.at(0, v));
  return out;
}

}  // namespace mocap
