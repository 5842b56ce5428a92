// The whole labelling path at 640x480 (bench/RESULTS.md): a recorded session of a tracked camera and 3
// tracked objects of about 20k triangles each, through `LabelSession` with every default output written
// (instance and class PNGs, rendered depth EXR, one packed mask PNG per frame, labels.jsonl) and the
// measured depth read for the visibility test. Reports labelled frames per second (wall clock, the whole
// run including loading the meshes), CPU time per frame over all threads and the rate two idle cores
// reach from it, and the workers' time per stage (render, read depth, labels, encode + write).
// Set LP_NUM_THREADS before the run (llvmpipe reads it once per process).
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "cpu_time.h"
#include "label/labeller.h"
#include "tests/pipeline/label_run_testing.h"
#include "render/primitives.h"
#include "session/image_io.h"
#include "session/writer.h"
#include "sim/kinect1_model.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
constexpr int64_t kMs = 1'000'000;
constexpr int kFrames = 120;
const PinholeCamera kCamera{640, 480, 525.0, 525.0, 319.5, 239.5, {}};

void WriteObj(const Mesh& mesh, const fs::path& path) {
  std::ofstream out(path);
  for (const auto& p : mesh.positions_m) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (size_t i = 0; i < mesh.indices.size(); i += 3)
    out << "f " << mesh.indices[i] + 1 << ' ' << mesh.indices[i + 1] + 1 << ' ' << mesh.indices[i + 2] + 1 << '\n';
}

/// Objects 0.7-1.0 m in front of a static camera, each moving 0.1 m/s sideways; a wall at 1.5 m.
Rigid3d ObjectPose(int i, int64_t t_ns) {
  const double s = static_cast<double>(t_ns) * 1e-9;
  return Rigid3d::FromRvec({0.3 * i, 0.2 + 0.5 * s, 0}, {-0.15 + 0.12 * i + 0.1 * s, 0.03 * i, 0.7 + 0.1 * i});
}

double SphereRadiusM(int i) { return 0.06 + 0.02 * i; }

/// What a Kinect v1 measures of the scene at `t_ns`: the spheres and the wall, ray-cast exactly, then
/// the sensor model's noise, disparity quantisation, shadows and dropped edges (sim/kinect1_model.h), so
/// the measured depth PNGs cost to decode what real ones do.
cv::Mat MeasuredDepth(int64_t t_ns, uint64_t seed) {
  DepthImage clean(kCamera.width, kCamera.height, 1.5f);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d c = ObjectPose(i, t_ns).translation();
    const double r2 = SphereRadiusM(i) * SphereRadiusM(i);
    for (int v = 0; v < kCamera.height; ++v)
      for (int u = 0; u < kCamera.width; ++u) {
        const Eigen::Vector3d d((u - kCamera.cx) / kCamera.fx, (v - kCamera.cy) / kCamera.fy, 1.0);
        const double dc = d.dot(c), disc = dc * dc - d.squaredNorm() * (c.squaredNorm() - r2);
        if (disc < 0) continue;
        const auto z = static_cast<float>((dc - std::sqrt(disc)) / d.squaredNorm());  // depth = ray parameter
        clean.at(u, v) = std::min(clean.at(u, v), z);
      }
  }
  sim::Kinect1Frame frame = sim::SimulateKinect1(clean, {}, kCamera, sim::Kinect1Options{}, seed);
  return cv::Mat(kCamera.height, kCamera.width, CV_32FC1, frame.depth_m.data.data()).clone();
}

fs::path WriteBenchSession(const fs::path& dir, std::vector<LabelObject>& objects) {
  SessionManifest manifest;
  manifest.source = "bench";
  CameraStreamInfo cam;
  cam.name = "kinect1";
  cam.model = "sim";
  cam.color_camera = cam.depth_camera = kCamera;
  cam.camera_body = "cambody";
  manifest.cameras.push_back(cam);
  manifest.trackers.push_back({"ndi", "sim", "", "tracker", {"cambody", "obj0", "obj1", "obj2"}});
  for (int i = 0; i < 3; ++i) {
    const fs::path mesh = dir / ("sphere" + std::to_string(i) + ".obj");
    WriteObj(MakeSphereMesh(SphereRadiusM(i), 20000), mesh);
    objects.push_back({.id = i + 1, .name = "sphere" + std::to_string(i), .object_class = "sphere",
                       .mesh_path = mesh, .unit_scale_to_m = 1.0, .mounts = {{"obj" + std::to_string(i), {}}}});
  }
  auto writer = SessionWriter::Create(dir / "S", manifest);
  for (int64_t t = 0; t <= (kFrames + 2) * 34 * kMs; t += 10 * kMs) {
    writer->WriteTrackerSample("ndi", {"cambody", PoseStatus::kValid, t / (10 * kMs), 0, t, Rigid3d(), 0, 0});
    for (int i = 0; i < 3; ++i)
      writer->WriteTrackerSample("ndi", {"obj" + std::to_string(i), PoseStatus::kValid, t / (10 * kMs), 0, t,
                                         ObjectPose(i, t), 0, 0});
  }
  const cv::Mat color(480, 640, CV_8UC3, cv::Scalar(90, 110, 130));
  for (int f = 0; f < kFrames; ++f) {
    CameraFrameRecord record;
    record.frame = f;
    record.stamp_ns = 20 * kMs + f * 33 * kMs;
    writer->WriteCameraFrame("kinect1", record, color, MeasuredDepth(record.stamp_ns, static_cast<uint64_t>(f)));
  }
  writer->Close();
  return dir / "S";
}

/// The process's kernel CPU time. Creating files on ext4 without a journal gets slower with every file
/// deleted in the last minutes (the inode allocator skips recently deleted inodes one by one), so the
/// same run costs more right after another (bench/RESULTS.md): this separates that from our own code.
double ProcessSystemSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_stime.tv_sec) + 1e-6 * static_cast<double>(usage.ru_stime.tv_usec);
}

/// Output variants: 0 = the defaults; 1 = also BOP-style full-size masks; 2 = defaults with ZIPS depth;
/// 3 = defaults without back-face culling (the defaults cull the closed spheres); 4 = no rendered depth; 5 = no mask files (these two split the
/// encode + write stage).
LabelRunOptions VariantOptions(const fs::path& out, int threads, int variant) {
  LabelRunOptions options;
  options.out_dir = out;
  options.threads = threads;
  options.output.write_bop_masks = variant == 1;
  if (variant == 2) options.output.depth_compression = DepthCompression::kZips;
  if (variant == 3) options.renderer.back_face_culling = BackFaceCulling::kNever;
  options.output.write_depth = variant != 4;
  options.output.write_masks = variant != 5;
  return options;
}

void BM_LabelSession(benchmark::State& state) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_bench_label_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::vector<LabelObject> objects;
  const SessionReader session = SessionReader::Open(WriteBenchSession(dir, objects));
  const LabelRunOptions options = VariantOptions(dir / "L", static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  double seconds = 0, setup_seconds = 0, frames_seconds = 0, frames_cpu_seconds = 0, cpu_seconds = 0,
         system_seconds = 0;
  LabelStageSeconds stages, stages_cpu;
  int64_t frames = 0;
  for (auto _ : state) {
    const double cpu0 = bench::ProcessCpuS(), system0 = ProcessSystemSeconds();
    const LabelSummary summary = LabelSession(session, objects, LabelRig{}, options);
    cpu_seconds += bench::ProcessCpuS() - cpu0;
    system_seconds += ProcessSystemSeconds() - system0;
    seconds += summary.seconds;
    setup_seconds += summary.setup_seconds;
    frames_seconds += summary.frames_seconds;
    frames_cpu_seconds += summary.frames_cpu_seconds;
    stages += summary.stages;
    stages_cpu += summary.stages_cpu;
    frames += summary.frames;
  }
  const double n = static_cast<double>(frames);
  state.counters["frames_per_s"] = n / seconds;
  // Without the run's fixed set-up (mesh loading, EGL contexts): the rate a long session sees.
  state.counters["frames_per_s_steady"] = n / frames_seconds;
  state.counters["setup_ms"] = 1e3 * setup_seconds / static_cast<double>(state.iterations());
  state.counters["cpu_ms_per_frame"] = 1e3 * cpu_seconds / n;
  state.counters["cpu_system_ms_per_frame"] = 1e3 * system_seconds / n;
  state.counters["fps_2_idle_cores"] = 2.0 * n / cpu_seconds;
  state.counters["render_share"] = stages.render / stages.total();
  // CPU time of the worker threads per stage: load-independent; with LP_NUM_THREADS=0 it is all the
  // rendering work, so cpu_render_share is the renderer's share on an idle machine.
  state.counters["cpu_render_share"] = stages_cpu.render / stages_cpu.total();
  // The same against all the process's CPU time: the set-up, the main thread and llvmpipe's own threads
  // (if any) counted as non-render too.
  state.counters["cpu_render_share_of_process"] = stages_cpu.render / cpu_seconds;
  // ... and against the process's CPU time from the first frame started to the last written (the
  // share a long session sees: the main thread and any llvmpipe threads counted, the set-up not).
  state.counters["cpu_render_share_of_process_steady"] = stages_cpu.render / frames_cpu_seconds;
  state.counters["cpu_render_ms"] = 1e3 * stages_cpu.render / n;
  state.counters["cpu_read_depth_ms"] = 1e3 * stages_cpu.read_depth / n;
  state.counters["cpu_labels_ms"] = 1e3 * stages_cpu.labels / n;
  state.counters["cpu_write_ms"] = 1e3 * stages_cpu.write / n;
  fs::remove_all(dir);
}
BENCHMARK(BM_LabelSession)
    ->ArgNames({"workers", "variant"})
    ->Args({1, 0})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Args({2, 2})
    ->Args({2, 3})
    ->Args({2, 4})
    ->Args({2, 5})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2)
    ->UseRealTime();

fs::path FreshBenchDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_bench_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The benchmark scene labelled once per process (uncompressed EXR, BOP-style masks too), for the codec
/// benchmarks below, which read frame 0's images back; removed at exit.
struct LabelledOnce {
  fs::path dir = FreshBenchDir("labelled");
  fs::path images;
  fs::path session_depth;  ///< frame 0's measured depth, as the session stores it (16-bit PNG)
  LabelledOnce() {
    std::vector<LabelObject> objects;
    const SessionReader session = SessionReader::Open(WriteBenchSession(dir, objects));
    session_depth = session.DepthPath("kinect1", 0);
    LabelRunOptions options = VariantOptions(dir / "L", 1, 1);
    options.output.depth_compression = DepthCompression::kNone;
    LabelSession(session, objects, LabelRig{}, options);
    images = dir / "L" / "kinect1";
  }
  ~LabelledOnce() { fs::remove_all(dir); }
};

const LabelledOnce& Labelled() {
  static const LabelledOnce labelled;
  return labelled;
}
const fs::path& LabelledImages() { return Labelled().images; }

/// Reading the session's measured depth (arg 0: ReadDepth, libdeflate + our row unfiltering, to float
/// metres; arg 1: OpenCV's imread through libpng + zlib, to 16-bit units only).
void BM_MeasuredDepthPng(benchmark::State& state) {
  const fs::path& png = Labelled().session_depth;
  for (auto _ : state) {
    if (state.range(0) == 0) {
      benchmark::DoNotOptimize(ReadDepth(png, 0.001));
    } else {
      benchmark::DoNotOptimize(cv::imread(png.string(), cv::IMREAD_ANYDEPTH));
    }
  }
  state.counters["kB"] = static_cast<double>(fs::file_size(png)) / 1e3;
  state.SetLabel(state.range(0) == 0 ? "ReadDepth (libdeflate)" : "cv::imread (libpng)");
}
BENCHMARK(BM_MeasuredDepthPng)->DenseRange(0, 1)->Unit(benchmark::kMillisecond);

/// Cost and size of each lossless OpenEXR codec on rendered depth (one thread).
void BM_DepthExrCodec(benchmark::State& state) {
  const fs::path dir = FreshBenchDir("exr");
  const DepthImage depth = ReadDepth(LabelledImages() / "depth" / "000000.exr", 1.0);
  const auto codec = static_cast<DepthCompression>(state.range(0));
  for (auto _ : state) WriteRenderedDepthExr(dir / "d.exr", depth, codec);
  state.counters["kB"] = static_cast<double>(fs::file_size(dir / "d.exr")) / 1e3;
  state.SetLabel(DepthCompressionName(codec));
  fs::remove_all(dir);
}
BENCHMARK(BM_DepthExrCodec)->DenseRange(0, 4)->Unit(benchmark::kMillisecond);

/// One label PNG of frame 0 (0: the 16-bit instance image; 1: a full-size 0/255 amodal mask; 2: the
/// frame's packed mask file), written with WriteLabelPng (arg 1 = 0) or with an explicit zlib
/// level 1 (arg 1 = 1: libpng then tries every row filter; what the labeller used before).
void BM_LabelPng(benchmark::State& state) {
  const fs::path dir = FreshBenchDir("png");
  const fs::path& images = LabelledImages();
  const char* sources[] = {"instance/000000.png", "mask/000000_000001.png", "mask_bits/000000.png"};
  const cv::Mat image = cv::imread((images / sources[state.range(0)]).string(), cv::IMREAD_UNCHANGED);
  const fs::path out = dir / "out.png";
  for (auto _ : state) {
    if (state.range(1) == 0) {
      WriteLabelPng(out, image);
    } else {
      cv::imwrite(out.string(), image, {cv::IMWRITE_PNG_COMPRESSION, 1});
    }
  }
  state.counters["kB"] = static_cast<double>(fs::file_size(out)) / 1e3;
  state.SetLabel(sources[state.range(0)]);
  fs::remove_all(dir);
}
BENCHMARK(BM_LabelPng)->ArgsProduct({{0, 1, 2}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
