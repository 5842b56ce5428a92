// The strict YAML readers: rig files (pipeline/rig.h), object libraries (pipeline/object_library.h),
// simulation scenarios (cli/scenario_yaml.h), pointer and landmarks files (cli/pointer_yaml.h). The first
// byte selects the reader (0 rig, 1 objects, 2 scenario, 3 pointer, 4 landmarks), the rest is the file. What reads is also written back and read again: the writer's text
// must read, and write the same text again (a file this tool writes must always load), numbers to 1e-12.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "cli/pointer_yaml.h"
#include "cli/scenario_yaml.h"
#include "fuzz_common.h"
#include "pipeline/object_library.h"
#include "pipeline/rig.h"

namespace {

/// Whether two written texts say the same: equal but for numbers within 1e-12 (relative). Not bit for bit:
/// reading normalises quaternions again, and normalising an already normalised quaternion may move its
/// last bit (Rigid3d's constructor, src/core/rigid3.cc).
bool SameText(const std::string& a, const std::string& b) {
  std::istringstream in_a(a), in_b(b);
  std::string token_a, token_b;
  while (in_a >> token_a) {
    if (!(in_b >> token_b)) return false;
    if (token_a == token_b) continue;
    auto number = [](std::string t) {
      while (!t.empty() && (t.back() == ',' || t.back() == ']' || t.back() == '}')) t.pop_back();
      while (!t.empty() && (t.front() == '[' || t.front() == '{')) t.erase(t.begin());
      char* end = nullptr;
      const double value = std::strtod(t.c_str(), &end);
      return (t.empty() || *end != '\0') ? std::nan("") : value;
    };
    const double x = number(token_a), y = number(token_b);
    if (!(std::abs(x - y) <= 1e-12 * std::max(1.0, std::abs(x)))) return false;
  }
  return !(in_b >> token_b);
}

/// Reads `text`, writes it, reads that and writes again: the written text must read, and the two written
/// texts must say the same (SameText).
template <typename Parse, typename Emit>
void RoundTrip(const char* what, const std::string& text, Parse parse, Emit emit, const std::string& name) {
  const std::string first = emit(parse(text, name));
  std::string second;
  try {
    second = emit(parse(first, "written " + name));
  } catch (const mocap::InputError& e) {
    std::fprintf(stderr, "fuzz_yaml: the written %s does not read back: %s\n--- written:\n%s\n", what, e.what(), first.c_str());
    std::abort();
  }
  if (!SameText(first, second)) {
    std::fprintf(stderr, "fuzz_yaml: the %s changes when written again\n--- first:\n%s\n--- second:\n%s\n", what, first.c_str(),
                 second.c_str());
    std::abort();
  }
}

void FuzzRig(const std::string& text) {
  using namespace mocap::pipeline;
  const Rig rig = ParseRig(text, "rig.yaml");
  (void)LabelRigOf(rig);
  if (rig.capture) (void)CaptureOptionsOf(rig);
  RoundTrip("rig", text, ParseRig, [](const Rig& r) { return EmitRig(r); }, "rig.yaml");
}

void FuzzObjects(const std::string& text) {
  using namespace mocap::pipeline;
  static const std::filesystem::path base = mocap::fuzz::FreshDir("objects");
  auto parse = [](const std::string& t, const std::string& name) { return ParseObjectLibrary(t, name, base); };
  const ObjectLibrary library = parse(text, "objects.yaml");
  (void)LabelObjectsOf(library);
  (void)ValidationObjectsOf(library);
  try {
    (void)SimObjectsOf(library);  // may refuse objects the simulator cannot place
  } catch (const mocap::InputError&) {
  }
  RoundTrip("object library", text, parse, [](const ObjectLibrary& l) { return EmitObjectLibrary(l); }, "objects.yaml");
}

void FuzzScenario(const std::string& text) {
  using namespace mocap::cli;
  (void)ParseScenarioYaml(text, "scenario.yaml");
  RoundTrip("scenario", text, ParseScenarioYaml, EncodeScenarioYaml, "scenario.yaml");
}

/// What a pointer or landmarks file reads to is finite and complete (the CLI writes pointer files with
/// the same emitter as the rig).
void FuzzPointer(const std::string& text) {
  using namespace mocap::cli;
  const PointerTool pointer = ParsePointer(text, "pointer.yaml");
  if (!pointer.tip_m.allFinite()) std::abort();
}

void FuzzLandmarks(const std::string& text) {
  const mocap::cli::Landmarks landmarks = mocap::cli::ParseLandmarks(text, "landmarks.yaml");
  if (landmarks.names.size() != landmarks.p_mesh_m.size() || landmarks.names.size() < 3) std::abort();
  for (const Eigen::Vector3d& p : landmarks.p_mesh_m)
    if (!p.allFinite()) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  mocap::fuzz::ExpectValueOrInputError("fuzz_yaml", [&] {
    switch (data[0] % 5) {
      case 0: return FuzzRig(text);
      case 1: return FuzzObjects(text);
      case 2: return FuzzScenario(text);
      case 3: return FuzzPointer(text);
      default: return FuzzLandmarks(text);
    }
  });
  return 0;
}
