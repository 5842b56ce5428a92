// Mesh files through the project's check (render/mesh_file_check.h) and then LoadMesh (assimp, not
// instrumented: a crash inside it still shows as a signal). The first byte picks the extension (0 .ply,
// 1 .obj, 2 .stl), the rest is the file. The in-memory check and the file check must agree, and a file
// the check passes must load or fail with an InputError, never crash assimp.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "fuzz_common.h"
#include "render/mesh.h"
#include "render/mesh_file_check.h"

// Assimp 5.2's STL text reader leaks its scene on some inputs (uninstrumented, not this project's code):
// suppressed by library name, so leaks in the project's code still fail the run.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::fuzz;
  if (size == 0) return 0;
  static const std::filesystem::path dir = FreshDir("mesh");
  const char* extensions[] = {".ply", ".obj", ".stl"};
  const std::string path = (dir / (std::string("mesh") + extensions[data[0] % 3])).string();
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  WriteFile(path, bytes);
  bool passes = true;
  try {
    mocap::CheckMeshBytes(bytes, path);
  } catch (const mocap::InputError&) {
    passes = false;
  }
  ExpectValueOrInputError("fuzz_mesh", [&] {
    mocap::MeshLoadOptions any_size;
    any_size.min_extent_m = any_size.max_extent_m = 0;
    (void)mocap::LoadMesh(path, 1.0, any_size);
    if (!passes) {
      std::fprintf(stderr, "fuzz_mesh: LoadMesh took a file CheckMeshBytes refuses\n");
      std::abort();
    }
  });
  return 0;
}
