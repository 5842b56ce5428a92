// BOP scene reading (session/import/bop_scene.h): one input is scene_gt.json, scene_camera.json and
// models_info.json joined with '\0', read as the scene folder 000002 whose rgb/ holds the images the
// real scene has (only their PNG headers: ReadBopScene reads the image size from the first one).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.h"
#include "session/import/bop_scene.h"

namespace {

namespace fs = std::filesystem;

/// The first 24 bytes of a 640x480 PNG: signature and the start of IHDR.
constexpr unsigned char kPngHeader[24] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                                          0, 0, 0x02, 0x80, 0, 0, 0x01, 0xE0};

/// The scene folder with its images; made once (the parser never writes to it).
const fs::path& SceneRoot() {
  static const fs::path root = [] {
    const fs::path scene = mocap::fuzz::FreshDir("bop") / "test" / "000002";
    fs::create_directories(scene / "rgb");
    fs::create_directories(scene / "depth");
    const std::string_view header(reinterpret_cast<const char*>(kPngHeader), sizeof(kPngHeader));
    for (const char* id : {"000000", "000001", "000003", "000008", "000017", "000027", "000036", "000038", "000039",
                           "000041", "000047", "000058"})
      mocap::fuzz::WriteFile(scene / "rgb" / (std::string(id) + ".png"), header);
    mocap::fuzz::WriteFile(scene / "depth" / "000003.png", header);
    fs::create_directories(scene.parent_path().parent_path() / "models");
    return scene;
  }();
  return root;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::fuzz;
  const fs::path& scene = SceneRoot();
  const fs::path models = scene.parent_path().parent_path() / "models";
  const auto parts = SplitParts(std::string_view(reinterpret_cast<const char*>(data), size), 3);
  const char* files[] = {"scene_gt.json", "scene_camera.json", "models_info.json"};
  for (size_t i = 0; i < 3; ++i) {
    const fs::path path = (i == 2 ? models : scene) / files[i];
    if (i < parts.size()) WriteFile(path, parts[i]);
    else fs::remove(path);
  }
  ExpectValueOrInputError("fuzz_bop", [&] { (void)mocap::import::ReadBopScene(scene, models); });
  return 0;
}
