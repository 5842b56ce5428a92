// Sustained recording capacity of the capture pipeline (sources -> bounded queues -> session writer)
// with unthrottled simulated sources, and zero-drop checks at fixed rates: a 640x480 RGB-D camera, a
// tracker, a Kinect v2 at its full sizes (JPEG colour stored as it came), and a Kinect v1 with a
// Kinect v2 (the Kinect runs pinned to two cores).
// Run: build/bench/bench_capture [--benchmark_filter=...]; results go into bench/RESULTS.md.
//
// Unthrottled sources push as fast as the recorder's queue has room (back-pressure instead of drops),
// so frames/s is the pipeline's capacity; the fixed-rate runs then check that a rate below it records
// with zero drops. CPU seconds per item are over all threads of the process (producer included), so
// `per_s_2_idle_cores` = 2 / cpu_per_item is the rate two otherwise idle cores would sustain.
#include <benchmark/benchmark.h>
#include <sched.h>
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

// Keeps this process (and the threads it starts from now on) on the first `cores` CPUs it may use, so a
// run on a bigger machine measures what two cores sustain. Returns the number pinned to.
int PinToCores(int cores) {
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (::sched_getaffinity(0, sizeof allowed, &allowed) != 0) return 0;
  cpu_set_t pinned;
  CPU_ZERO(&pinned);
  int n = 0;
  for (int cpu = 0; cpu < CPU_SETSIZE && n < cores; ++cpu)
    if (CPU_ISSET(cpu, &allowed)) {
      CPU_SET(cpu, &pinned);
      ++n;
    }
  return ::sched_setaffinity(0, sizeof pinned, &pinned) == 0 ? n : 0;
}

struct RigSpec {
  std::vector<SimulatedCameraOptions> cameras{};  ///< rate 0: unthrottled with back-pressure
  double tracker_hz = 0;
  int bodies = 0;  ///< 0: no tracker
  double seconds = 6;
  int pin_cores = 0;  ///< 0: as the machine gives
  SessionWriterOptions writer{};
};

// Records `spec.seconds` from the cameras and the tracker through one Recorder (a queue per camera).
void RunRig(benchmark::State& state, const RigSpec& spec) {
  const int pinned = spec.pin_cores > 0 ? PinToCores(spec.pin_cores) : 0;
  for (auto _ : state) {
    const fs::path dir = FreshSession("rig");
    std::unique_ptr<Recorder> recorder;
    const int frame_queue = RecorderOptions{}.frame_queue;
    std::vector<std::unique_ptr<CaptureSource>> sources;
    for (const SimulatedCameraOptions& camera : spec.cameras) {
      auto ready = [&recorder, name = camera.stream, frame_queue] { return recorder->frame_queue_depth(name) + 2 < static_cast<size_t>(frame_queue); };
      sources.push_back(CreateSimulatedCamera(camera, ready));
    }
    if (spec.bodies > 0) {
      auto ready = [&] { return recorder->sample_queue_depth() + 64 < 8192; };
      sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = spec.bodies, .rate_hz = spec.tracker_hz}, ready));
    }
    std::vector<CaptureSource*> raw;
    for (auto& s : sources) raw.push_back(s.get());
    recorder = Recorder::Start({.session_dir = dir, .writer = spec.writer}, ManifestOf(raw));
    const double cpu0 = bench::ProcessCpuS();
    const auto t0 = std::chrono::steady_clock::now();
    for (auto& s : sources) {
      s->Open();
      s->Start(recorder.get());
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(spec.seconds));
    for (auto& s : sources) s->Close();
    const RecorderSummary summary = recorder->Stop();
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_s = bench::ProcessCpuS() - cpu0;
    state.SetIterationTime(wall_s);
    int64_t items = 0;
    for (const auto& [stream, c] : summary.streams) {
      const std::string prefix = stream == "trk" ? "samples" : stream == "cam" ? "frames" : stream;
      state.counters[prefix + "_per_s"] = static_cast<double>(c.written) / wall_s;
      state.counters[prefix + "_dropped"] = static_cast<double>(c.dropped);
      state.counters[prefix + "_written"] = static_cast<double>(c.written);
      items += c.written;
    }
    if (sources.size() == 1) {
      state.counters["cpu_ms_per_item"] = 1e3 * cpu_s / static_cast<double>(items);
      state.counters["per_s_2_idle_cores"] = 2.0 * static_cast<double>(items) / cpu_s;
    }
    state.counters["cpu_cores_used"] = cpu_s / wall_s;
    if (pinned > 0) state.counters["pinned_cores"] = pinned;
    if (!summary.complete) state.SkipWithError(("session failed: " + summary.error).c_str());
    fs::remove_all(dir.parent_path());
  }
}

SimulatedCameraOptions Cam(double rate_hz) { return {.stream = "cam", .rate_hz = rate_hz}; }
SimulatedCameraOptions AtRate(SimulatedCameraOptions camera, double rate_hz) {
  camera.rate_hz = rate_hz;
  return camera;
}

void BM_CameraUnthrottled(benchmark::State& s) { RunRig(s, {.cameras = {Cam(0)}, .seconds = 6}); }
void BM_Camera90Hz(benchmark::State& s) { RunRig(s, {.cameras = {Cam(90)}, .seconds = 6}); }
void BM_TrackerUnthrottled(benchmark::State& s) { RunRig(s, {.tracker_hz = 0, .bodies = 4, .seconds = 4}); }
void BM_Tracker4000PerS(benchmark::State& s) { RunRig(s, {.tracker_hz = 1000, .bodies = 4, .seconds = 4}); }
// The goal rig at once: 90 camera frames/s and 4000 tracker samples/s (4 bodies at 1000 Hz).
void BM_Camera90HzWithTracker4000PerS(benchmark::State& s) {
  RunRig(s, {.cameras = {Cam(90)}, .tracker_hz = 1000, .bodies = 4, .seconds = 6});
}
// A Kinect v2 at its full sizes: 1920x1080 colour as JPEG as the device sends it (stored without
// decoding) and 512x424 depth (16-bit PNG), 30 Hz, on two cores; its capacity unthrottled.
void BM_Kinect2At30HzOn2Cores(benchmark::State& s) {
  RunRig(s, {.cameras = {SimulatedKinect2("kinect2")}, .seconds = 30, .pin_cores = 2});
}
void BM_Kinect2UnthrottledOn2Cores(benchmark::State& s) {
  RunRig(s, {.cameras = {AtRate(SimulatedKinect2("kinect2"), 0)}, .seconds = 8, .pin_cores = 2});
}
// For comparison, the same Kinect v2 had its colour been decoded (as libfreenect2's stock pipelines
// hand it over): 1920x1080 BGR pixels encoded by the writer as PNG, or again as JPEG (quality 95).
SimulatedCameraOptions Kinect2Pixels() {
  SimulatedCameraOptions camera = AtRate(SimulatedKinect2("kinect2"), 0);
  camera.color_jpeg = false;
  return camera;
}
void BM_Kinect2PixelsAsPngUnthrottledOn2Cores(benchmark::State& s) {
  RunRig(s, {.cameras = {Kinect2Pixels()}, .seconds = 8, .pin_cores = 2});
}
void BM_Kinect2PixelsAsJpegUnthrottledOn2Cores(benchmark::State& s) {
  RunRig(s, {.cameras = {Kinect2Pixels()}, .seconds = 8, .pin_cores = 2, .writer = {.color_encoding = ColorEncoding::kJpeg}});
}
// A Kinect v1 (640x480 PNG colour + depth) and a Kinect v2 at full size together, 30 Hz each, with a
// 4-body tracker at 100 Hz, on two cores.
void BM_Kinect1AndKinect2At30HzOn2Cores(benchmark::State& s) {
  RunRig(s, {.cameras = {SimulatedKinect1("kinect1"), SimulatedKinect2("kinect2")}, .tracker_hz = 100, .bodies = 4,
             .seconds = 30, .pin_cores = 2});
}

BENCHMARK(BM_CameraUnthrottled)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Camera90Hz)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_TrackerUnthrottled)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Tracker4000PerS)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Camera90HzWithTracker4000PerS)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Kinect2At30HzOn2Cores)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Kinect2UnthrottledOn2Cores)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Kinect2PixelsAsPngUnthrottledOn2Cores)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Kinect2PixelsAsJpegUnthrottledOn2Cores)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);
BENCHMARK(BM_Kinect1AndKinect2At30HzOn2Cores)->Iterations(1)->UseManualTime()->Unit(benchmark::kSecond);

}  // namespace
}  // namespace mocap::capture

BENCHMARK_MAIN();
