// Sustained recording capacity of the capture pipeline (sources -> bounded queues -> session writer)
// with unthrottled simulated sources, and zero-drop checks at fixed rates.
// Run: build/bench/bench_capture [--benchmark_filter=...]; results go into bench/RESULTS.md.
//
// Unthrottled sources push as fast as the recorder's queue has room (back-pressure instead of drops),
// so frames/s is the pipeline's capacity; the fixed-rate runs then check that a rate below it records
// with zero drops. CPU seconds per item are over all threads of the process (producer included), so
// `per_s_2_idle_cores` = 2 / cpu_per_item is the rate two otherwise idle cores would sustain.
#include <benchmark/benchmark.h>
#include <time.h>
#include <unistd.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "cpu_time.h"
#include "capture/daemon/recorder.h"
#include "capture/daemon/sources.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

fs::path FreshSession(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("bench_capture_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  return dir;
}

SessionManifest ManifestOf(const std::vector<CaptureSource*>& sources) {
  SessionManifest manifest;
  manifest.source = "bench";
  for (const CaptureSource* source : sources) AddStream(manifest, source->stream_info());
  return manifest;
}

// Records `seconds` from a camera and/or tracker; rate 0 = unthrottled with back-pressure.
void RunRig(benchmark::State& state, double camera_hz, bool camera, double tracker_hz, int bodies, double seconds) {
  for (auto _ : state) {
    const fs::path dir = FreshSession("rig");
    std::unique_ptr<Recorder> recorder;
    auto frames_ready = [&] { return recorder->frame_queue_depth() + 2 < 32; };
    auto samples_ready = [&] { return recorder->sample_queue_depth() + 64 < 8192; };
    std::vector<std::unique_ptr<CaptureSource>> sources;
    if (camera) sources.push_back(CreateSimulatedCamera({.stream = "cam", .rate_hz = camera_hz}, frames_ready));
    if (bodies > 0)
      sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = bodies, .rate_hz = tracker_hz}, samples_ready));
    std::vector<CaptureSource*> raw;
    for (auto& s : sources) raw.push_back(s.get());
    recorder = Recorder::Start({.session_dir = dir}, ManifestOf(raw));
    const double cpu0 = bench::ProcessCpuS();
    const auto t0 = std::chrono::steady_clock::now();
    for (auto& s : sources) {
      s->Open();
      s->Start(recorder.get());
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    for (auto& s : sources) s->Close();
    const RecorderSummary summary = recorder->Stop();
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_s = bench::ProcessCpuS() - cpu0;
    state.SetIterationTime(wall_s);
    for (const char* stream : {"cam", "trk"}) {
      if (!summary.streams.count(stream)) continue;
      const StreamCounters& c = summary.streams.at(stream);
      const std::string prefix = stream == std::string("cam") ? "frames" : "samples";
      state.counters[prefix + "_per_s"] = static_cast<double>(c.written) / wall_s;
      state.counters[prefix + "_dropped"] = static_cast<double>(c.dropped);
      state.counters[prefix + "_written"] = static_cast<double>(c.written);
      if (sources.size() == 1) {
        state.counters["cpu_ms_per_item"] = 1e3 * cpu_s / static_cast<double>(c.written);
        state.counters["per_s_2_idle_cores"] = 2.0 * static_cast<double>(c.written) / cpu_s;
      }
    }
    state.counters["cpu_cores_used"] = cpu_s / wall_s;
    if (!summary.complete) state.SkipWithError(("session failed: " + summary.error).c_str());
    fs::remove_all(dir.parent_path());
  }
}

void BM_CameraUnthrottled(benchmark::State& s) { RunRig(s, 0, true, 0, 0, 6.0); }
void BM_Camera90Hz(benchmark::State& s) { RunRig(s, 90, true, 0, 0, 6.0); }
void BM_TrackerUnthrottled(benchmark::State& s) { RunRig(s, 0, false, 0, 4, 4.0); }
void BM_Tracker4000PerS(benchmark::State& s) { RunRig(s, 0, false, 1000, 4, 4.0); }
// The goal rig at once: 90 camera frames/s and 4000 tracker samples/s (4 bodies at 1000 Hz).
void BM_Camera90HzWithTracker4000PerS(benchmark::State& s) { RunRig(s, 90, true, 1000, 4, 6.0); }

BENCHMARK(BM_CameraUnthrottled)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Camera90Hz)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_TrackerUnthrottled)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Tracker4000PerS)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Camera90HzWithTracker4000PerS)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
}  // namespace mocap::capture

BENCHMARK_MAIN();
