// The export a user runs (`mocaplabel export`; bench/RESULTS.md "Export"): a simulated session of the
// default scenario (120 Kinect v1 frames, 640x480) recorded and labelled once per process (masks on, the
// default), then `RunExport` end to end per iteration, from files: load the runs, select, write,
// provenance, publish, with `--split none`. Every iteration writes a new folder; all are removed at exit.
// Counters: frames/s and ms/frame (wall clock), and the export's phases per frame.
//
// The peer, in the same run: how a user's script writes the same BOP masks without our writer:
// full-image 0/255 masks by cv::imwrite (PNG, OpenCV's defaults) and rgb/depth by
// std::filesystem::copy_file, from the same loaded and decoded label run (bop_toolkit is Python).
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <thread>
#include <utility>

#include "core/check.h"
#include "core/progress.h"
#include "exporters/export/export.h"
#include "label/label_output.h"
#include "pipeline/label_stage.h"
#include "pipeline/record_stage.h"

namespace mocap::exporters {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
constexpr int kFrames = 120;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// The session and its label run, made once: recording and labelling cost far more than an export, and
/// every benchmark must read the same files. Outputs are kept until exit, when all is removed: deleting
/// thousands of files just before creating as many makes ext4 skip the recently freed inodes, a cost a
/// user exporting into a new folder does not pay (bench/RESULTS.md "Export").
struct SimulatedRun {
  fs::path root, session, labels;
  SimulatedRun() : root(fs::temp_directory_path() / ("bench_export_" + std::to_string(::getpid()))) {
    fs::remove_all(root);
    session = root / "S", labels = root / "L";
    sim::Scenario scenario = sim::DefaultScenario();
    scenario.options.frame_count = kFrames;
    sim::RecordOptions record;
    record.out_dir = session, record.threads = 2;
    const pipeline::SimRecordResult recorded = pipeline::RecordSimulatedSession(scenario, nullptr, record);
    pipeline::LabelRunRequest request;
    request.session_dir = session, request.rig_file = recorded.rig_file, request.objects_file = recorded.objects_file;
    request.out_dir = labels, request.label.threads = 2, request.command = {"mocaplabel", "label"};
    pipeline::RunLabel(request);
  }
  ~SimulatedRun() { fs::remove_all(root); }
  std::vector<ExportInput> inputs() const { return {{session, labels, {}, false}}; }
  /// A folder no iteration has used.
  fs::path FreshOutput() const { return root / "out" / std::to_string(++outputs); }
  mutable int outputs = 0;
};

const SimulatedRun& Run() {
  static const SimulatedRun run;
  return run;
}

/// Drops the inputs' pages from the page cache, so the next export reads them from the disk (as for a
/// session recorded days ago). Written back first (dirty pages cannot be dropped); only these files,
/// not drop_caches: the machine is shared. The VM host's cache may still serve some reads.
void EvictFromPageCache(const std::vector<fs::path>& dirs) {
  for (const fs::path& dir : dirs)
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
      if (!entry.is_regular_file()) continue;
      const int fd = ::open(entry.path().c_str(), O_RDONLY | O_CLOEXEC);
      if (fd < 0) continue;
      ::fdatasync(fd);
      ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
      ::close(fd);
    }
}

/// Keeps the time of the export's first step (loading the runs): Progress always reports its first
/// Advance, whatever its reporting interval.
class LoadTimeSink : public ProgressSink {
 public:
  void Report(const ProgressUpdate& update) override {
    if (!update.finished && update.done >= 1 && load_s < 0) load_s = update.elapsed_s;
  }
  double load_s = -1;
};

/// frames/s over the timed wall clock; ms/frame from `seconds`, the timed region as measured here.
void SetRateCounters(benchmark::State& state, int64_t frames, double seconds) {
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  state.counters["ms_per_frame"] = 1e3 * seconds / static_cast<double>(std::max<int64_t>(frames, 1));
}

/// One timed RunExport per iteration into a fresh folder. `cold`: the inputs are evicted first (untimed).
/// The first export of the process is printed apart: its inputs were just written.
void TimedExports(benchmark::State& state, const ExportOptions& options, bool cold) {
  const SimulatedRun& run = Run();
  static bool first_of_process = true;
  int64_t frames = 0;
  double load_s = 0, write_s = 0, publish_s = 0, total_s = 0;
  for (auto _ : state) {
    if (cold) {
      state.PauseTiming();
      EvictFromPageCache({run.session, run.labels});
      state.ResumeTiming();
    }
    LoadTimeSink sink;
    const auto start = Clock::now();
    const ExportResult result = RunExport(run.inputs(), options, run.FreshOutput(), {"mocaplabel", "export"}, &sink);
    const double seconds = SecondsSince(start);
    frames += result.written.images, total_s += seconds;
    // result.seconds ends before export.json is written and the folder published.
    load_s += sink.load_s, write_s += result.seconds - sink.load_s, publish_s += seconds - result.seconds;
    if (std::exchange(first_of_process, false))
      std::fprintf(stderr, "first export of the process (%s, %d threads%s): %.1f ms/frame\n",
                   std::string(ToString(options.format)).c_str(), options.threads, cold ? ", cold" : "",
                   1e3 * seconds / static_cast<double>(result.written.images));
  }
  SetRateCounters(state, frames, total_s);
  const double per_frame_ms = 1e3 / static_cast<double>(std::max<int64_t>(frames, 1));
  state.counters["load_ms"] = load_s * per_frame_ms;  // read the runs, open the session
  state.counters["select_write_ms"] = write_s * per_frame_ms;  // filters, the format's files, run.json
  state.counters["publish_ms"] = publish_s * per_frame_ms;  // export.json, rename into place
}

ExportOptions Options(ExportFormat format, int64_t threads) {
  ExportOptions options;
  options.format = format;
  options.threads = static_cast<int>(threads);
  options.splits.by = SplitBy::kNone;
  return options;
}

void BM_ExportBop(benchmark::State& state) { TimedExports(state, Options(ExportFormat::kBop, state.range(0)), false); }
void BM_ExportBopColdInputs(benchmark::State& state) {
  TimedExports(state, Options(ExportFormat::kBop, state.range(0)), true);
}
void BM_ExportCoco(benchmark::State& state) { TimedExports(state, Options(ExportFormat::kCoco, state.range(0)), false); }

std::string Padded(int64_t value) {
  char text[32];
  std::snprintf(text, sizeof text, "%06lld", static_cast<long long>(value));
  return text;
}

cv::Mat FullImage(const std::vector<uint8_t>& mask, const PixelRect& rect, int width, int height) {
  return rect.empty() ? cv::Mat::zeros(height, width, CV_8UC1) : FullMaskImage(mask, rect, width, height);
}

/// The peer's work for one frame, as a script would write it: copy the recorded images, decode the
/// frame's masks, one cv::imwrite per mask.
void PeerFrame(const Dataset& dataset, const ExportFrame& frame, const fs::path& dir) {
  const ExportScene& scene = dataset.scene_of(frame);
  const std::string im = Padded(frame.im_id);
  fs::copy_file(frame.color_path, dir / "rgb" / (im + frame.color_path.extension().string()));
  fs::copy_file(frame.depth_path, dir / "depth" / (im + ".png"));
  const std::vector<ObjectMasks> masks = ReadFrameMasks(scene, frame);
  const int width = scene.color_camera.width, height = scene.color_camera.height;
  for (size_t i = 0, gt = 0; i < masks.size(); ++i) {
    const pipeline::LabelRecord& record = frame.instances[i].record;
    if (!record.has_pose) continue;
    const std::string name = im + "_" + Padded(static_cast<int64_t>(gt++)) + ".png";
    if (!cv::imwrite((dir / "mask" / name).string(), FullImage(masks[i].amodal, masks[i].rect, width, height)) ||
        !cv::imwrite((dir / "mask_visib" / name).string(), FullImage(VisibleMask(masks[i], record), masks[i].rect, width, height)))
      throw InputError(name, "cv::imwrite failed");
  }
}

/// The peer end to end from files like ours: the same load and selection, then PeerFrame over the
/// frames on range(0) threads. No scene JSON, models, provenance or publish: the image files only.
void BM_PeerBopImages(benchmark::State& state) {
  const SimulatedRun& run = Run();
  const int threads = static_cast<int>(state.range(0));
  int64_t frames = 0;
  double total_s = 0;
  for (auto _ : state) {
    const auto start = Clock::now();
    const fs::path dir = run.FreshOutput() / "train" / "000001";
    Dataset dataset = LoadDataset(run.inputs());
    SelectFrames(dataset, ExportFilterOptions{}, ExportSplitOptions{.by = SplitBy::kNone});
    for (const char* sub : {"rgb", "depth", "mask", "mask_visib"}) fs::create_directories(dir / sub);
    std::atomic<size_t> next{0};
    auto worker = [&] {
      for (size_t i = next++; i < dataset.frames.size(); i = next++) PeerFrame(dataset, dataset.frames[i], dir);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    frames += static_cast<int64_t>(dataset.frames.size()), total_s += SecondsSince(start);
  }
  SetRateCounters(state, frames, total_s);
}

/// One phase alone: decoding every frame's packed masks (what both writers do before encoding).
void BM_ReadFrameMasksOnly(benchmark::State& state) {
  Dataset dataset = LoadDataset(Run().inputs());
  SelectFrames(dataset, ExportFilterOptions{}, ExportSplitOptions{.by = SplitBy::kNone});
  double total_s = 0;
  for (auto _ : state) {
    const auto start = Clock::now();
    for (const ExportFrame& frame : dataset.frames) benchmark::DoNotOptimize(ReadFrameMasks(dataset.scene_of(frame), frame));
    total_s += SecondsSince(start);
  }
  SetRateCounters(state, static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(dataset.frames.size()), total_s);
}

// Wall clock (the writers run threads); CPU column = the whole process's CPU time.
BENCHMARK(BM_ExportBop)->Arg(2)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
BENCHMARK(BM_ExportBopColdInputs)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
BENCHMARK(BM_ExportCoco)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
BENCHMARK(BM_PeerBopImages)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();
BENCHMARK(BM_ReadFrameMasksOnly)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

}  // namespace
}  // namespace mocap::exporters

BENCHMARK_MAIN();
