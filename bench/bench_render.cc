// Label rendering throughput at 640x480 (bench/RESULTS.md): 3 objects of about 20k triangles each,
// instance ids + depth + one amodal layer per object, optionally with the label computation (three masks
// and BOP statistics against a measured depth image). Mesa's llvmpipe uses LP_NUM_THREADS rasteriser
// threads (default: the number of cores); set it in the environment to measure 1 or 2 cores.
#include <benchmark/benchmark.h>

#include <random>

#include "label/object_labels.h"
#include "render/primitives.h"
#include "render/renderer.h"

namespace mocap {
namespace {

const PinholeCamera kCamera{640, 480, 525.0, 525.0, 319.5, 239.5, {}};

struct Scene {
  std::unique_ptr<RenderContext> context;
  std::unique_ptr<Renderer> renderer;
  std::vector<RenderItem> items;
  DepthImage measured;

  Scene(int objects, int triangles, bool distorted, int margin_percent = 100, bool cull = false) {
    context = RenderContext::Create();
    renderer = std::make_unique<Renderer>(
        *context, RendererOptions{.outside_margin_fraction = margin_percent / 100.0,
                                  .back_face_culling = cull ? BackFaceCulling::kAlways : BackFaceCulling::kNever});
    // Objects of 6-10 cm radius at 0.7-1.0 m, overlapping in the image as on a table top.
    for (int i = 0; i < objects; ++i) {
      const MeshHandle mesh = renderer->Upload(MakeSphereMesh(0.06 + 0.02 * (i % 3), triangles));
      items.push_back({mesh, Rigid3d::FromRvec({0.3 * i, 0.2, 0}, {-0.15 + 0.12 * i, 0.03 * i, 0.7 + 0.1 * i}),
                       static_cast<uint16_t>(i + 1)});
    }
    camera = kCamera;
    if (distorted) camera.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
    // "Measured" depth: the rendered scene with Kinect-like noise and 5% missing pixels.
    measured = renderer->Render(camera, items).depth_m;
    std::mt19937 rng(1);
    std::normal_distribution<float> noise(0.0f, 1.0f);
    std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
    for (float& z : measured.data) {
      if (z == 0.0f) z = 1.5f;  // a table behind the objects
      z = uniform(rng) < 0.05f ? 0.0f : z + 1.425e-3f * z * z * noise(rng);
    }
  }
  PinholeCamera camera;
};

void SetCounters(benchmark::State& state, const Scene& scene) {
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["objects"] = static_cast<double>(scene.items.size());
}

/// Render only: id + depth images and one amodal layer per object (output buffers reused).
void BM_Render(benchmark::State& state) {
  Scene scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0);
  RenderOutput render;
  for (auto _ : state) {
    scene.renderer->Render(scene.camera, scene.items, render);
    benchmark::DoNotOptimize(render.layers.data());
  }
  SetCounters(state, scene);
}

/// Render only, back faces culled when range(4) is 1, with a canvas margin of range(3) percent of the image size on each side (100 = BOP's
/// 3x canvas, 0 = no amodal counts outside the image).
void BM_RenderOptions(benchmark::State& state) {
  Scene scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0,
              static_cast<int>(state.range(3)), state.range(4) != 0);
  RenderOutput render;
  for (auto _ : state) {
    scene.renderer->Render(scene.camera, scene.items, render);
    benchmark::DoNotOptimize(render.layers.data());
  }
  SetCounters(state, scene);
}
BENCHMARK(BM_RenderOptions)->ArgNames({"objects", "triangles", "distorted", "margin", "cull"})->Args({3, 20000, 0, 0, 0})->Args({3, 20000, 0, 100, 1})->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();

/// Render + labels: three masks per object and the BOP statistics against the measured depth.
void BM_RenderAndLabel(benchmark::State& state) {
  Scene scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0);
  RenderOutput render;
  for (auto _ : state) {
    scene.renderer->Render(scene.camera, scene.items, render);
    benchmark::DoNotOptimize(ComputeObjectLabels(render, scene.camera, &scene.measured));
  }
  SetCounters(state, scene);
}

/// Labels alone (the non-render share of BM_RenderAndLabel).
void BM_LabelOnly(benchmark::State& state) {
  Scene scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), state.range(2) != 0);
  const RenderOutput render = scene.renderer->Render(scene.camera, scene.items);
  for (auto _ : state) benchmark::DoNotOptimize(ComputeObjectLabels(render, scene.camera, &scene.measured));
  SetCounters(state, scene);
}

// Arguments: objects, triangles per object, distorted camera (0/1).
#define MOCAP_RENDER_ARGS ArgNames({"objects", "triangles", "distorted"})->Args({3, 20000, 0})->Args({3, 20000, 1})->Args({3, 2000, 0})->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime()
BENCHMARK(BM_Render)->MOCAP_RENDER_ARGS;
BENCHMARK(BM_RenderAndLabel)->MOCAP_RENDER_ARGS;
BENCHMARK(BM_LabelOnly)->MOCAP_RENDER_ARGS;

}  // namespace
}  // namespace mocap

BENCHMARK_MAIN();
