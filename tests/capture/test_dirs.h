#pragma once
// Fresh per-test folders under the build tree. Test support only.
#include <filesystem>
#include <string>

namespace mocap::testing {

inline std::filesystem::path FreshCaptureDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(MOCAP_BINARY_DIR) / "test_output" / "capture" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace mocap::testing
