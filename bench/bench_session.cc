// Session writer and reader throughput on real 640x480 Kinect1 frames (TUM fr1/desk RGB + 16-bit depth).
// Run: build/bench/bench_session [--benchmark_filter=...]; results go into bench/RESULTS.md.
#include <benchmark/benchmark.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "cpu_time.h"
#include "session/image_io.h"
#include "session/reader.h"
#include "session/writer.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

struct TumFrames {
  std::vector<cv::Mat> color, depth;
};

/// The 9 real RGB-D frames of TUM fr1/desk, read once.
const TumFrames& Frames() {
  static const TumFrames frames = [] {
    TumFrames out;
    const fs::path root = fs::path(MOCAP_SHARED_DIR) / "realdata/tum_fr1_desk_9frames";
    for (const char* kind : {"rgb", "depth"}) {
      std::vector<fs::path> paths;
      for (const auto& entry : fs::directory_iterator(root / kind)) paths.push_back(entry.path());
      std::sort(paths.begin(), paths.end());
      for (const auto& path : paths) {
        cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
        if (image.empty()) throw std::runtime_error("cannot read " + path.string());
        (std::string(kind) == "rgb" ? out.color : out.depth).push_back(image);
      }
    }
    return out;
  }();
  return frames;
}

SessionManifest Manifest() {
  SessionManifest manifest;
  manifest.source = "bench";
  CameraStreamInfo camera;
  camera.name = "kinect1";
  camera.model = "kinect1";
  camera.color_camera = {640, 480, 517.3, 516.5, 318.6, 255.3, {}};
  camera.depth_camera = camera.color_camera;
  camera.depth_unit_m = 1.0 / 5000.0;
  camera.camera_body = "cam";
  manifest.cameras = {camera};
  manifest.trackers = {{"ndi", "sim", "", "tracker", {"cam", "obj"}}};
  return manifest;
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mocap_bench_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  return dir;
}

/// Frames per second written (encoded, stored, recorded), including the final Close().
/// Args: encoder threads, sync_images (0/1), colour JPEG (0/1).
void BM_WriteRgbdFrames(benchmark::State& state) {
  const TumFrames& frames = Frames();
  SessionWriterOptions options;
  options.encoder_threads = static_cast<int>(state.range(0));
  options.sync_images = state.range(1) != 0;
  options.color_encoding = state.range(2) ? ColorEncoding::kJpeg : ColorEncoding::kPng;
  options.png_compression = static_cast<int>(state.range(3));
  const fs::path dir = FreshDir("write");
  int64_t written = 0;
  const double cpu_start_s = bench::ProcessCpuS();
  {
    auto writer = SessionWriter::Create(dir, Manifest(), options);
    for (auto _ : state) {
      const size_t k = static_cast<size_t>(written) % frames.color.size();
      writer->WriteCameraFrame("kinect1", {written, 0, written * 33'333'333, "", "", ""}, frames.color[k],
                               frames.depth[k]);
      ++written;
    }
    writer->Close();
  }
  state.SetItemsProcessed(written);
  // CPU seconds per frame over all threads: on a shared, loaded machine the wall rate understates what
  // two free cores do; cores / cpu_per_frame is the rate two idle cores would reach.
  const double cpu_per_frame_s = (bench::ProcessCpuS() - cpu_start_s) / static_cast<double>(written);
  state.counters["cpu_ms_per_frame"] = cpu_per_frame_s * 1e3;
  state.counters["fps_2_idle_cores"] = 2.0 / cpu_per_frame_s;
  fs::remove_all(dir);
}
BENCHMARK(BM_WriteRgbdFrames)
    ->ArgNames({"threads", "sync_images", "jpeg", "png_level"})
    ->Args({1, 0, 0, -1})
    ->Args({2, 0, 0, -1})
    ->Args({3, 0, 0, -1})
    ->Args({2, 1, 0, -1})
    ->Args({2, 0, 1, -1})
    ->Args({2, 0, 0, 1})
    ->Iterations(300)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

void BM_WriteTrackerSamples(benchmark::State& state) {
  const fs::path dir = FreshDir("tracker");
  int64_t written = 0;
  {
    auto writer = SessionWriter::Create(dir, Manifest());
    TrackerRecord record;
    record.body = "cam";
    for (auto _ : state) {
      record.device_frame = written;
      record.stamp_ns = written * 10'000'000;
      record.T_frame_body = Rigid3d::FromRvec({0.001 * static_cast<double>(written), 0.2, 0.3}, {0.1, 0.2, 1.5});
      writer->WriteTrackerSample("ndi", record);
      ++written;
    }
    writer->Close();
  }
  state.SetItemsProcessed(written);
  fs::remove_all(dir);
}
BENCHMARK(BM_WriteTrackerSamples)->UseRealTime();

/// A session of 90 RGB-D frames (3 s of Kinect1) and 3 s of 2-body tracking at 100 Hz, written once.
const fs::path& ReadSession() {
  static const fs::path dir = [] {
    const fs::path dir = FreshDir("read");
    auto writer = SessionWriter::Create(dir, Manifest());
    const TumFrames& frames = Frames();
    for (int64_t i = 0; i < 90; ++i) {
      const size_t k = static_cast<size_t>(i) % frames.color.size();
      writer->WriteCameraFrame("kinect1", {i, 0, i * 33'333'333, "", "", ""}, frames.color[k], frames.depth[k]);
    }
    for (int64_t i = 0; i < 300; ++i) {
      for (const char* body : {"cam", "obj"}) {
        TrackerRecord record;
        record.body = body;
        record.stamp_ns = i * 10'000'000;
        writer->WriteTrackerSample("ndi", record);
      }
    }
    writer->Close();
    return dir;
  }();
  return dir;
}

/// Frames per second loaded (colour decoded to BGR, depth to metres), random access by index.
void BM_ReadRgbdFrames(benchmark::State& state) {
  const SessionReader reader = SessionReader::Open(ReadSession());
  int64_t read = 0;
  for (auto _ : state) {
    const int64_t index = (read * 37) % reader.frame_count("kinect1");
    benchmark::DoNotOptimize(reader.LoadColor("kinect1", index).data);
    benchmark::DoNotOptimize(reader.LoadDepth("kinect1", index).data.data());
    ++read;
  }
  state.SetItemsProcessed(read);
}
BENCHMARK(BM_ReadRgbdFrames)->UseRealTime()->Unit(benchmark::kMillisecond);

/// Opening a session: manifest, every record (90 frames, 600 tracker samples) checksummed and parsed.
void BM_OpenSession(benchmark::State& state) {
  const fs::path& dir = ReadSession();
  for (auto _ : state) benchmark::DoNotOptimize(SessionReader::Open(dir).frame_count("kinect1"));
  state.SetItemsProcessed(state.iterations() * 690);
}
BENCHMARK(BM_OpenSession)->UseRealTime()->Unit(benchmark::kMillisecond);

/// Where DepthPngs writes its files (removed at exit).
const fs::path& DepthPngDir() {
  static const fs::path dir = FreshDir("depth_png");
  return dir;
}

/// The 9 TUM depth frames as PNG files: 0 = written by the session writer (EncodeDepthPng: libdeflate,
/// session/png_write.h), 1 = by OpenCV's speed path (libpng, zlib level 1, RLE; the writer before),
/// 2 = TUM's own files as recorded (what an imported session reads). Written once per source.
const std::vector<fs::path>& DepthPngs(int source) {
  static std::vector<fs::path> files[3];
  if (!files[source].empty()) return files[source];
  const fs::path dir = DepthPngDir() / std::to_string(source);
  fs::create_directories(dir);
  const fs::path tum = fs::path(MOCAP_SHARED_DIR) / "realdata/tum_fr1_desk_9frames/depth";
  std::vector<fs::path> originals;
  for (const auto& entry : fs::directory_iterator(tum)) originals.push_back(entry.path());
  std::sort(originals.begin(), originals.end());
  if (source == 2) return files[source] = originals;
  for (size_t k = 0; k < originals.size(); ++k) {
    std::vector<uint8_t> bytes;
    if (source == 0) bytes = EncodeDepthPng(Frames().depth[k], 1.0 / 5000.0, -1);
    else cv::imencode(".png", Frames().depth[k], bytes);
    files[source].push_back(dir / (std::to_string(k) + ".png"));
    std::ofstream(files[source].back(), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                                static_cast<std::streamsize>(bytes.size()));
  }
  return files[source];
}

double MeanKiloBytes(const std::vector<fs::path>& files) {
  double bytes = 0;
  for (const fs::path& f : files) bytes += static_cast<double>(fs::file_size(f));
  return bytes / static_cast<double>(files.size()) / 1e3;
}

const char* DepthPngSource(int source) {
  const char* names[] = {"session writer (libdeflate)", "OpenCV speed path (libpng)", "TUM's files"};
  return names[source];
}

/// Encoding one real Kinect depth frame to PNG bytes (0: EncodeDepthPng; 1: cv::imencode's speed path).
void BM_DepthPngEncode(benchmark::State& state) {
  const TumFrames& frames = Frames();
  size_t k = 0;
  for (auto _ : state) {
    const cv::Mat& depth = frames.depth[k++ % frames.depth.size()];
    std::vector<uint8_t> bytes;
    if (state.range(0) == 0) bytes = EncodeDepthPng(depth, 1.0 / 5000.0, -1);
    else cv::imencode(".png", depth, bytes);
    benchmark::DoNotOptimize(bytes.data());
  }
  state.counters["kB"] = MeanKiloBytes(DepthPngs(static_cast<int>(state.range(0))));
  state.SetLabel(DepthPngSource(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_DepthPngEncode)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

/// Reading one depth PNG file to metres (ReadDepth: libdeflate + our row unfiltering), by who wrote it.
void BM_DepthPngRead(benchmark::State& state) {
  const std::vector<fs::path>& files = DepthPngs(static_cast<int>(state.range(0)));
  size_t k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ReadDepth(files[k++ % files.size()], 1.0 / 5000.0).data.data());
  state.counters["kB"] = MeanKiloBytes(files);
  state.SetLabel(DepthPngSource(static_cast<int>(state.range(0))));
}
BENCHMARK(BM_DepthPngRead)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mocap

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::filesystem::remove_all(mocap::ReadSession());
  std::filesystem::remove_all(mocap::DepthPngDir());
  return 0;
}
