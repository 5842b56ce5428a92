// SegICP validator benchmark on real Kinect data (PCL's milk scene, model = milk.pcd, true pose =
// identity): the acquisition (30 hypotheses, coarse stage on crop subsets, the best 2 refined) and one
// tracking step, with our ICP and with pcl::IterativeClosestPoint on the same clouds, hypotheses and
// scores, in one run. Prints the ratios. Also the scene index alone: nanoflann (KdTree) against our
// cell grid (PointGrid), build and queries.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <random>
#include <string>

#include "../tests/validate/pcd_reader.h"
#include "pcl_baseline.h"
#include "validate/acquisition.h"
#include "validate/kdtree.h"
#include "validate/pose_filter.h"
#include "validate/validate_options.h"

namespace mocap {
namespace {

struct Fixture {
  PointCloud model, scene;
  std::unique_ptr<SurfaceCropSource> source;
  std::vector<Rigid3d> priors;   // acquisition starts, up to 3 cm / 20 deg off
  Rigid3d predicted;             // tracking prediction, 5 mm / 2 deg off
  ValidateOptions options;
};

Rigid3d AboutCenter(const Rigid3d& delta, const Eigen::Vector3d& c) {
  return Rigid3d::FromRvec({0, 0, 0}, delta.translation() + c) * Rigid3d(delta.rotation(), -(delta.rotation() * c));
}

Rigid3d Perturbation(std::mt19937& rng, double t_m, double deg) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  return Rigid3d::FromRvec(axis * RadFromDeg(deg), dir * t_m);
}

const Fixture& Data() {
  static const Fixture f = [] {
    Fixture x;
    const std::string dir = std::string(MOCAP_SHARED_DIR) + "/realdata/pcl/";
    x.model = testing::FinitePoints(testing::ReadPcd(dir + "milk.pcd").points);
    const Box3d box = BoundingBox(x.model, 0.015);
    for (const auto& p : testing::FinitePoints(testing::ReadPcd(dir + "milk_cartoon_all_small_clorox.pcd").points))
      if (box.contains(p)) x.scene.push_back(p);
    x.scene = VoxelDownsample(x.scene, x.options.scene_voxel_m);
    x.source = std::make_unique<SurfaceCropSource>(x.model, x.options.crop);
    std::mt19937 rng(21);
    const Eigen::Vector3d c = Centroid(x.model);
    for (int i = 0; i < 8; ++i) x.priors.push_back(AboutCenter(Perturbation(rng, 0.03, 20.0), c));
    x.predicted = AboutCenter(Perturbation(rng, 0.005, 2.0), c);
    return x;
  }();
  return f;
}

/// Worst error against the true pose (the identity) over the benchmark's iterations (the starts cycle).
void Report(benchmark::State& state, const Rigid3d& estimate) {
  const double mm = 1e3 * TranslationDistanceM(estimate, Rigid3d::Identity());
  const double deg = RotationDistanceDeg(estimate, Rigid3d::Identity());
  state.counters["worst_mm"] = std::max(static_cast<double>(state.counters["worst_mm"]), mm);
  state.counters["worst_deg"] = std::max(static_cast<double>(state.counters["worst_deg"]), deg);
}

void BM_Acquisition_Ours(benchmark::State& state) {
  const Fixture& f = Data();
  size_t k = 0;
  for (auto _ : state) {
    const PointGrid grid(f.scene);
    const AcquisitionResult r = AcquireAround(f.scene, grid, *f.source, f.priors[k++ % f.priors.size()],
                                              f.options.acquisition, f.options.alignment);
    Report(state, r.T_camera_model);
  }
}

/// Every `stride`-th point, lowered to keep 50 points (AcquisitionOptions::hypothesis_stride's rule).
PointCloud EveryNth(const PointCloud& points, int stride) {
  stride = std::min(stride, std::max(1, static_cast<int>(points.size()) / 50));
  PointCloud out;
  for (size_t i = 0; i < points.size(); i += static_cast<size_t>(stride)) out.push_back(points[i]);
  return out;
}

/// Indices of `scores`, best first (the acquisition's rule without the RMSE tie-break: PCL's ICP does
/// not report our inlier RMSE; ties keep the hypothesis order).
std::vector<size_t> Ranked(const std::vector<double>& scores) {
  std::vector<size_t> order(scores.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return scores[a] > scores[b]; });
  return order;
}

/// The same acquisition with pcl::IterativeClosestPoint as the registration: the same hypotheses (crops
/// and starts taken from our acquisition, untimed), the coarse stage on the same crop subsets (PCL ICP,
/// 5 cm, as many iterations as ours) scored by the same metric, the best refine_count re-cropped and
/// refined by PCL ICP (1 cm, 100 iterations, all points) and scored in full; the best of those wins.
void BM_Acquisition_Pcl(benchmark::State& state) {
  const Fixture& f = Data();
  const AcquisitionOptions& acq = f.options.acquisition;
  std::vector<AcquisitionResult> setups;
  for (const auto& prior : f.priors) {
    const PointGrid grid(f.scene);
    setups.push_back(AcquireAround(f.scene, grid, *f.source, prior, acq, f.options.alignment));
  }
  const bench::PclIcpSettings coarse{acq.icp.initial_correspondence_distance_m, acq.icp.max_iterations, 1e-8};
  const bench::PclIcpSettings refine{acq.refine_icp.max_correspondence_distance_m, acq.refine_icp.max_iterations, 1e-10};
  size_t k = 0;
  for (auto _ : state) {
    const AcquisitionResult& s = setups[k++ % setups.size()];
    const bench::PclScene pcl_scene(f.scene);
    const PointGrid grid(f.scene);
    const int n = static_cast<int>(s.hypotheses.size());
    std::vector<Rigid3d> poses(n);
    std::vector<double> scores(n);
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < n; ++i) {
      const PointCloud crop = EveryNth(s.crops[s.hypotheses[i].crop_index].points_model, acq.hypothesis_stride);
      poses[i] = pcl_scene.Align(crop, s.hypotheses[i].T_camera_model_init, coarse);
      scores[i] = ScoreAlignment(crop, poses[i], grid, f.options.alignment).score;
    }
    const std::vector<size_t> order = Ranked(scores);
    const int count = std::min(acq.refine_count, n);
    std::vector<Rigid3d> refined(count);
    std::vector<double> refined_scores(count);
#pragma omp parallel for schedule(dynamic, 1)
    for (int j = 0; j < count; ++j) {
      const ModelCrop crop = f.source->Crop(poses[order[j]]);
      refined[j] = pcl_scene.Align(crop.points_model, poses[order[j]], refine);
      refined_scores[j] = ScoreAlignment(crop.points_model, refined[j], grid, f.options.alignment).score;
    }
    Report(state, refined[Ranked(refined_scores).front()]);
  }
}

void BM_Tracking_Ours(benchmark::State& state) {
  const Fixture& f = Data();
  const Box3d box = BoundingBox(f.source->surface_model(), f.options.tracking.box_margin_m);
  PoseFilter filter(f.options.filter);
  filter.Initialize(f.predicted, 0, 1.0);
  int64_t stamp = 0;
  for (auto _ : state) {
    filter.Predict(stamp += 33'333'333);
    const PointCloud pruned = CropToBox(f.scene, f.predicted, box);
    const PointGrid grid(pruned);
    const ModelCrop crop = f.source->Crop(f.predicted);
    const IcpResult r = AlignPointToPoint(crop.points_model, grid, f.predicted, f.options.tracking.icp);
    state.counters["icp_its"] = r.iterations;
    const double score = ScoreAlignment(crop.points_model, r.T_target_source, grid, f.options.alignment).score;
    benchmark::DoNotOptimize(filter.Update(r.T_target_source, score));
    Report(state, r.T_target_source);
  }
}

void BM_Tracking_Pcl(benchmark::State& state) {
  const Fixture& f = Data();
  const Box3d box = BoundingBox(f.source->surface_model(), f.options.tracking.box_margin_m);
  const bench::PclIcpSettings settings{f.options.tracking.icp.initial_correspondence_distance_m,
                                       f.options.tracking.icp.max_iterations, 1e-10};
  for (auto _ : state) {
    const PointCloud pruned = CropToBox(f.scene, f.predicted, box);
    const bench::PclScene pcl_scene(pruned);
    const PointGrid grid(pruned);
    const ModelCrop crop = f.source->Crop(f.predicted);
    const Rigid3d T = pcl_scene.Align(crop.points_model, f.predicted, settings);
    benchmark::DoNotOptimize(ScoreAlignment(crop.points_model, T, grid, f.options.alignment).score);
    Report(state, T);
  }
}

/// The scene index on its own: nanoflann's kd-tree (KdTree) against our cell grid (PointGrid), on the
/// queries an acquisition makes. "start": every hypothesis's crop subset at its start pose (gate 5 cm,
/// no hint: the first ICP pass); "near": the refined crops at their final poses (gate 1 cm), without a
/// hint (the alignment score) or with the match of the same point 1 mm away as the hint (ICP passes).
struct IndexQueries {
  PointCloud start, near, near_hint_from;
};

const IndexQueries& Queries() {
  static const IndexQueries q = [] {
    const Fixture& f = Data();
    IndexQueries x;
    const PointGrid grid(f.scene);
    const Eigen::Vector3d offset = Eigen::Vector3d(1, -1, 1).normalized() * 0.001;
    for (const auto& prior : f.priors) {
      const AcquisitionResult r = AcquireAround(f.scene, grid, *f.source, prior, f.options.acquisition, f.options.alignment);
      for (const auto& h : r.hypotheses)
        for (const auto& p : EveryNth(r.crops[h.crop_index].points_model, f.options.acquisition.hypothesis_stride))
          x.start.push_back(h.T_camera_model_init * p);
      for (const auto& p : r.refined_crop.points_model) {
        x.near.push_back(r.T_camera_model * p);
        x.near_hint_from.push_back(x.near.back() + offset);
      }
    }
    return x;
  }();
  return q;
}

template <class Index>
void BM_SceneIndex_Build(benchmark::State& state) {
  const Fixture& f = Data();
  for (auto _ : state) benchmark::DoNotOptimize(Index(f.scene).size());
  state.counters["points"] = static_cast<double>(f.scene.size());
}

/// Range 0: 0 = start queries, 1 = near without a hint, 2 = near with a hint. Sums the distances found
/// (equal for both indexes, up to float rounding: the results agree).
template <class Index>
void BM_SceneIndex_Query(benchmark::State& state) {
  const Fixture& f = Data();
  const IndexQueries& q = Queries();
  const Index index(f.scene);
  const int kind = static_cast<int>(state.range(0));
  const PointCloud& queries = kind == 0 ? q.start : q.near;
  const double gate_m = kind == 0 ? 0.05 : 0.01;
  std::vector<size_t> hints(queries.size(), Index::kNoHint);
  double d2 = 0.0;
  if (kind == 2)
    for (size_t i = 0; i < queries.size(); ++i) index.Nearest(q.near_hint_from[i], gate_m, &hints[i], &d2);
  double sum_m2 = 0.0;
  for (auto _ : state) {
    sum_m2 = 0.0;
    for (size_t i = 0; i < queries.size(); ++i) {
      size_t match = hints[i];
      if (index.NearestFrom(queries[i], gate_m, &match, &d2)) sum_m2 += d2;
    }
    benchmark::DoNotOptimize(sum_m2);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * queries.size()));
  state.counters["queries"] = static_cast<double>(queries.size());
  state.counters["sum_d2_mm2"] = sum_m2 * 1e6;
}

BENCHMARK_TEMPLATE(BM_SceneIndex_Build, KdTree)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_SceneIndex_Build, PointGrid)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_SceneIndex_Query, KdTree)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK_TEMPLATE(BM_SceneIndex_Query, PointGrid)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);

BENCHMARK(BM_Acquisition_Ours)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(16);
BENCHMARK(BM_Acquisition_Pcl)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(8);  // all 8 starts
BENCHMARK(BM_Tracking_Ours)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK(BM_Tracking_Pcl)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);

/// Console output plus the per-benchmark real time, for the ratios printed at the end.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const auto& run : runs) ms_[run.benchmark_name()] = run.GetAdjustedRealTime();
    ConsoleReporter::ReportRuns(runs);
  }
  void PrintRatios() const {
    for (const char* phase : {"Acquisition", "Tracking"}) {
      const auto find = [&](const std::string& prefix) {
        auto it = ms_.lower_bound(prefix);
        return it != ms_.end() && it->first.rfind(prefix, 0) == 0 ? it : ms_.end();
      };
      const auto ours = find(std::string("BM_") + phase + "_Ours/");
      const auto pcl = find(std::string("BM_") + phase + "_Pcl/");
      if (ours != ms_.end() && pcl != ms_.end())
        std::printf("%s: ours %.2f ms, PCL %.2f ms, PCL/ours = %.1fx (%d threads)\n", phase, ours->second,
                    pcl->second, pcl->second / ours->second, omp_get_max_threads());
    }
  }

 private:
  std::map<std::string, double> ms_;
};

}  // namespace
}  // namespace mocap

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  mocap::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintRatios();
  return 0;
}
