// OptiTrack Motive CSV exports (session/import/motive_csv.h): the input is the file.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"
#include "session/import/motive_csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::fuzz;
  static const std::filesystem::path file = FreshDir("motive") / "take.csv";
  WriteFile(file, std::string_view(reinterpret_cast<const char*>(data), size));
  ExpectValueOrInputError("fuzz_motive", [&] { (void)mocap::import::ReadMotiveCsv(file); });
  return 0;
}
