// TUM RGB-D sequence reading (session/import/tum.h): one input is rgb.txt, depth.txt and
// groundtruth.txt joined with '\0', read as a sequence folder and associated (ReadTumSequence).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"
#include "session/import/tum.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::fuzz;
  static const std::filesystem::path dir = FreshDir("tum");
  const auto parts = SplitParts(std::string_view(reinterpret_cast<const char*>(data), size), 3);
  const char* files[] = {"rgb.txt", "depth.txt", "groundtruth.txt"};
  for (size_t i = 0; i < 3; ++i) WriteFile(dir / files[i], i < parts.size() ? parts[i] : std::string_view());
  ExpectValueOrInputError("fuzz_tum", [&] { (void)mocap::import::ReadTumSequence(dir); });
  return 0;
}
