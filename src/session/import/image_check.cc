#include "session/import/image_check.h"

#include <algorithm>
#include <array>
#include <string>
#include <fstream>
#include <vector>

#include "core/check.h"
#include "core/text.h"

namespace mocap::import {
namespace {

constexpr std::array<unsigned char, 8> kPngSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
// Length 0, "IEND", CRC: the last 12 bytes of every complete PNG.
constexpr std::array<unsigned char, 12> kPngEnd = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};

std::vector<unsigned char> ReadRange(std::ifstream& in, std::streamoff offset, size_t count) {
  std::vector<unsigned char> bytes(count);
  in.seekg(offset);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(count));
  bytes.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  in.clear();
  return bytes;
}

}  // namespace

void CheckImageComplete(const std::filesystem::path& image) {
  std::ifstream in(image, std::ios::binary);
  if (!in) throw InputError(image.string(), "cannot open the image");
  const auto size = static_cast<std::streamoff>(std::filesystem::file_size(image));
  const auto head = ReadRange(in, 0, 8);
  const size_t tail_size = static_cast<size_t>(std::min<std::streamoff>(size, 16));
  const auto tail = ReadRange(in, size - static_cast<std::streamoff>(tail_size), tail_size);
  if (head.size() == 8 && std::equal(kPngSignature.begin(), kPngSignature.end(), head.begin())) {
    if (tail.size() < kPngEnd.size() || !std::equal(kPngEnd.begin(), kPngEnd.end(), tail.end() - kPngEnd.size()))
      throw InputError(Str(image.string(), ": byte ", size),
                       "PNG is truncated or corrupt (no IEND chunk at its end); restore the file or drop it from the list");
    return;
  }
  if (head.size() >= 2 && head[0] == 0xFF && head[1] == 0xD8) {
    // Some writers pad after the EOI marker; accept it within the last 16 bytes.
    for (size_t i = 0; i + 1 < tail.size(); ++i)
      if (tail[i] == 0xFF && tail[i + 1] == 0xD9) return;
    throw InputError(Str(image.string(), ": byte ", size),
                     "JPEG is truncated or corrupt (no end-of-image marker); restore the file or drop it from the list");
  }
  throw InputError(image.string(), "neither a PNG nor a JPEG image");
}

void CheckImportableImage(const std::filesystem::path& image, bool depth) {
  const std::string ext = LowerExtension(image);
  const bool ok = depth ? ext == ".png" : (ext == ".png" || ext == ".jpg");
  if (!ok)
    throw InputError(image.string(), depth ? "depth images must be 16-bit PNG files" : "colour images must be PNG or JPEG files");
  if (std::filesystem::exists(image)) CheckImageComplete(image);
}

}  // namespace mocap::import
