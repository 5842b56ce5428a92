#include "label/depth_exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <Iex.h>

#include <array>
#include <utility>

#include "core/check.h"
#include "label/exr_rle.h"
#include "label/label_png.h"

namespace mocap {
namespace {

constexpr std::array<std::pair<DepthCompression, const char*>, 5> kNames{{{DepthCompression::kNone, "none"},
                                                                          {DepthCompression::kRle, "rle"},
                                                                          {DepthCompression::kZips, "zips"},
                                                                          {DepthCompression::kZip, "zip"},
                                                                          {DepthCompression::kPiz, "piz"}}};

Imf::Compression ToImf(DepthCompression c) {
  switch (c) {
    case DepthCompression::kNone: return Imf::NO_COMPRESSION;
    case DepthCompression::kRle: return Imf::RLE_COMPRESSION;
    case DepthCompression::kZips: return Imf::ZIPS_COMPRESSION;
    case DepthCompression::kZip: return Imf::ZIP_COMPRESSION;
    case DepthCompression::kPiz: return Imf::PIZ_COMPRESSION;
  }
  return Imf::NO_COMPRESSION;
}

}  // namespace

DepthCompression DepthCompressionFromString(const std::string& name) {
  for (const auto& [value, n] : kNames)
    if (name == n) return value;
  throw InputError("depth compression", "'" + name + "' is not one of none, rle, zips, zip, piz");
}

const char* DepthCompressionName(DepthCompression compression) {
  for (const auto& [value, n] : kNames)
    if (value == compression) return n;
  return "?";
}

void WriteRenderedDepthExr(const std::filesystem::path& path, const DepthImage& depth_m, DepthCompression compression) {
  // RLE, the default, is encoded here (exr_rle.h: OpenEXR's writer costs more than the compression).
  if (compression == DepthCompression::kRle && !depth_m.data.empty())
    return WriteFileBytes(path, EncodeDepthExrRle(depth_m));
  try {
    Imf::Header header(depth_m.width, depth_m.height);
    header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
    header.compression() = ToImf(compression);
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer buffer;
    // OpenEXR's Slice takes a mutable pointer but only reads through it when writing.
    char* base = reinterpret_cast<char*>(const_cast<float*>(depth_m.data.data()));
    buffer.insert("Z", Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * depth_m.width));
    file.setFrameBuffer(buffer);
    file.writePixels(depth_m.height);
  } catch (const Iex::BaseExc& e) {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
    throw InputError(path.string(), Str("cannot write OpenEXR depth: ", e.what()));
  }
}

}  // namespace mocap
