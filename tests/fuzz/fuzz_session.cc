// The session reader (session/reader.h, manifest.h, records.h, record_file.h). The first byte selects:
// bit 0 re-frames every stream line with a fresh checksum (else mutated lines mostly fail their CRC and
// the fuzzer only reaches the checksum test), bit 1 reads with skip_corrupt_records. The rest is
// manifest.json, then the stream files in SessionStreamFiles order, then events.jsonl, joined with '\0'.
// Stream files go only where the parsed manifest puts them (its names are checked to be plain names).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_common.h"
#include "session/reader.h"
#include "session/record_file.h"

namespace {

namespace fs = std::filesystem;

/// Each line's JSON with a fresh "\t<crc32>" (any old checksum dropped), as the writer frames it. A
/// last line without '\n' stays without one (a torn tail).
std::string Reframe(std::string_view stream) {
  std::string out;
  while (!stream.empty()) {
    const size_t end = stream.find('\n');
    std::string_view line = stream.substr(0, end);
    const size_t tab = line.rfind('\t');
    if (tab != std::string_view::npos && line.size() - tab == 9) line = line.substr(0, tab);
    char crc[16];
    std::snprintf(crc, sizeof(crc), "\t%08x", mocap::Crc32(line));
    out.append(line).append(crc);
    if (end == std::string_view::npos) break;
    out += '\n';
    stream.remove_prefix(end + 1);
  }
  return out;
}

/// Everything a labelling run asks the reader for.
void Exercise(const mocap::SessionReader& reader) {
  const mocap::SessionManifest& manifest = reader.manifest();
  for (const auto& camera : manifest.cameras) {
    const int64_t frames = reader.frame_count(camera.name);
    for (int64_t i = 0; i < frames && i < 64; ++i) {
      (void)reader.ColorPath(camera.name, i);
      (void)reader.CameraPoseAtFrame(camera.name, i);
      for (const auto& tracker : manifest.trackers)
        for (const auto& body : tracker.bodies) (void)reader.SamplesAroundFrame(camera.name, i, tracker.name, body);
    }
  }
  for (const auto& tracker : manifest.trackers)
    for (const auto& body : tracker.bodies) {
      (void)reader.BodyRecords(tracker.name, body);
      (void)reader.PoseSamples(tracker.name, body);
      (void)reader.TrackerOfBody(body);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace mocap::fuzz;
  if (size == 0) return 0;
  const bool reframe = data[0] & 1;
  mocap::SessionReaderOptions options;
  options.skip_corrupt_records = data[0] & 2;
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  const fs::path dir = FreshDir("session");
  const size_t kMaxParts = 16;
  const auto parts = SplitParts(bytes, kMaxParts);
  WriteFile(dir / "manifest.json", parts[0]);
  ExpectValueOrInputError("fuzz_session", [&] {
    const mocap::SessionManifest manifest = mocap::LoadManifest(dir);
    std::vector<fs::path> streams = mocap::SessionStreamFiles(manifest);
    streams.front() = "events.jsonl";  // manifest.json is written already; events last
    std::rotate(streams.begin(), streams.begin() + 1, streams.end());
    for (size_t i = 0; i < streams.size() && i + 1 < parts.size(); ++i) {
      const std::string stream = reframe ? Reframe(parts[i + 1]) : std::string(parts[i + 1]);
      fs::create_directories((dir / streams[i]).parent_path());
      WriteFile(dir / streams[i], stream);
    }
    Exercise(mocap::SessionReader::Open(dir, options));
  });
  return 0;
}
