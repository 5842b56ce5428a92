// PLUS sequence metafiles (session/import/plus_mha.h): the input is the .mha file.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"
#include "session/import/plus_mha.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::fuzz;
  static const std::filesystem::path file = FreshDir("plus") / "sequence.igs.mha";
  WriteFile(file, std::string_view(reinterpret_cast<const char*>(data), size));
  ExpectValueOrInputError("fuzz_plus", [&] { (void)mocap::import::ReadPlusSequence(file); });
  return 0;
}
