// The validator on the user's path (bench/RESULTS.md "bench_validate_session"): `mocaplabel validate`'s
// library call (pipeline::RunValidate: session, label run and meshes read from files, validation.jsonl,
// validation.json and report.html written) on each case given, once per registration backend, all in this
// one process and run, so that the ratios hold whatever else loads the machine:
//   segicp   the validator's own ICP (the default)
//   pcl      pcl::IterativeClosestPoint / IterativeClosestPointWithNormals  (built when PCL is found)
//   open3d   Open3D's RegistrationICP loop, PointToPoint / PointToPlane      (built when Open3D is found)
// Everything but the registration (crops, scene clouds, scores, the observability analysis, the verdicts)
// is the validator's own in all three (validate/registration.h).
//
// Per case and backend: records/s (records with a pose over the wall time), wall and CPU time, the share
// of the CPU time in the registration (every call timed on its thread), in reading the frames and in the
// scene clouds (both replayed alone as the session check does them: each frame's depth and instance PNGs
// read once, each record's cloud cut, thinned and indexed once), and the rest (crops,
// scores, the observability analysis, filter and verdicts, writing the outputs). Accuracy: correct labels
// accepted (the cases' labels are correct: a simulated session's with its true calibration, LM-O's ground
// truth), SegICP success (the paper's criterion), and the estimate's position / rotation error against the
// truth (the simulated truth/poses.jsonl with --truth, else the label), median and p95.
//
// Usage:
//   bench_validate_session [--out DIR] [--repeat N] [--backends segicp,pcl,open3d] CASE...
//     CASE: --name NAME --session S --labels L [--objects O] [--truth T]
//   bench_validate_session --make-lmo DIR     LM-O scene 2 imported and labelled, with depth (prints the CASE)
// The commands that make the cases are in bench/RESULTS.md.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/check.h"
#include "pipeline/label_run.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/validate_stage.h"
#include "registration_backends.h"
#include "cpu_time.h"
#include "validate_session_report.h"
#include "render/mesh.h"
#include "session/image_io.h"
#include "session/reader.h"
#include "validate/point_grid.h"
#include "validate/session_check.h"
#if MOCAP_BENCH_WITH_LMO
#include "tests/validate/session_fixture.h"
#endif

namespace mocap::bench {
namespace {

namespace fs = std::filesystem;

/// A backend with the CPU time of every call added up (each on its own thread's clock).
class TimedRegistration final : public Registration {
 public:
  explicit TimedRegistration(std::shared_ptr<const Registration> inner) : inner_(std::move(inner)) {}
  std::string_view name() const override { return inner_->name(); }
  IcpResult PointToPoint(const PointCloud& source, const PointGrid& scene, const Rigid3d& T_init,
                         const IcpOptions& options) const override {
    const double start = ThreadCpuS();
    IcpResult r = inner_->PointToPoint(source, scene, T_init, options);
    Add(point_to_point_ns_, start);
    return r;
  }
  IcpResult PointToPlane(const ModelCrop& crop, const PointGrid& scene, const Rigid3d& T_init,
                         const ObservabilityOptions& options, double first_gate_m, PlaneRefinement* refinement) const override {
    const double start = ThreadCpuS();
    IcpResult r = inner_->PointToPlane(crop, scene, T_init, options, first_gate_m, refinement);
    Add(point_to_plane_ns_, start);
    return r;
  }
  double point_to_point_s() const { return 1e-9 * static_cast<double>(point_to_point_ns_.load()); }
  double point_to_plane_s() const { return 1e-9 * static_cast<double>(point_to_plane_ns_.load()); }

 private:
  static void Add(std::atomic<int64_t>& total_ns, double start_s) {
    total_ns += static_cast<int64_t>(1e9 * (ThreadCpuS() - start_s));
  }
  std::shared_ptr<const Registration> inner_;
  mutable std::atomic<int64_t> point_to_point_ns_{0}, point_to_plane_ns_{0};
};

struct Case {
  std::string name;
  fs::path session, labels, objects, truth;
};

/// Reading the frames and making the scene clouds, replayed alone on one thread as the session check
/// does them: each frame's depth and instance PNG read once for all of its records (the session check
/// shares them between its jobs), and per record the object's cloud cut from the depth, thinned once and
/// indexed once. The session check's cut of what the depth shows in front of the object (its occluder
/// cut, which needs the label's crop) is not replayed: it counts under "rest".
ReplayedSteps ReplaySteps(const Case& c, const pipeline::LabelRun& labels) {
  const SessionReader session = SessionReader::Open(c.session);
  const std::vector<ValidationObject> objects =
      pipeline::ValidationObjectsOf(pipeline::ReadObjectLibrary(pipeline::FindObjectsFile(c.session, c.objects)));
  std::map<int, double> voxel_m;
  for (const ValidationObject& o : objects)
    voxel_m[o.id] = OptionsForObject(LoadMesh(o.mesh_path.string(), o.unit_scale_to_m), ValidateOptions()).scene_voxel_m;
  std::map<std::pair<std::string, int64_t>, std::vector<const pipeline::LabelRecord*>> frames;
  for (const pipeline::LabelRecord& r : labels.records)
    if (r.has_pose && session.frame(r.camera, r.index).depth_present) frames[{r.camera, r.index}].push_back(&r);
  ReplayedSteps steps;
  for (const auto& [frame, records] : frames) {
    const auto& [camera_name, index] = frame;
    double start = ThreadCpuS();
    const DepthImage depth_m = session.LoadDepth(camera_name, index);
    const LabelImage mask = ReadIdImage(labels.layout.InstancePng(camera_name, index));
    steps.io_s += ThreadCpuS() - start;
    start = ThreadCpuS();
    const PinholeCamera& camera = session.manifest().FindCamera(camera_name)->color_camera;
    for (const pipeline::LabelRecord* r : records) {
      const PointCloud cloud = DepthToPointsMasked(depth_m, camera, mask, static_cast<uint16_t>(r->instance));
      const PointGrid grid(VoxelDownsample(cloud, voxel_m.at(r->object)));
      benchmark::DoNotOptimize(grid.size());
    }
    steps.scene_cloud_s += ThreadCpuS() - start;
  }
  return steps;
}

BackendRun RunBackend(const Case& c, const pipeline::LabelRun& labels, const std::shared_ptr<const Registration>& backend,
                      const fs::path& out) {
  // Ours through the same timer: SegIcpRegistration is what the default (null) registration runs.
  const auto timed = std::make_shared<TimedRegistration>(backend ? backend : std::make_shared<SegIcpRegistration>());
  pipeline::ValidateRunRequest request;
  request.session_dir = c.session, request.labels_dir = c.labels, request.objects_file = c.objects;
  request.out_dir = out / c.name / std::string(timed->name());
  fs::remove_all(request.out_dir);
  request.check.validate.acquisition.registration = timed;
  const double cpu_start = ProcessCpuS();
  const auto wall_start = std::chrono::steady_clock::now();
  const SessionValidation v = pipeline::RunValidate(request);
  BackendRun run;
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  run.cpu_s = ProcessCpuS() - cpu_start;
  run.backend = std::string(timed->name());
  run.point_to_point_s = timed->point_to_point_s();
  run.point_to_plane_s = timed->point_to_plane_s();
  ScoreRun(v, labels, c.truth, &run);
  return run;
}

/// The backends named in `names` (comma-separated), in that order; ours (null) is "segicp".
std::vector<std::shared_ptr<const Registration>> Backends(const std::string& names) {
  std::vector<std::shared_ptr<const Registration>> backends;
  for (size_t begin = 0; begin <= names.size();) {
    const size_t end = std::min(names.find(',', begin), names.size());
    const std::string name = names.substr(begin, end - begin);
    begin = end + 1;
    if (name == "segicp") backends.push_back(nullptr);
#if MOCAP_BENCH_WITH_PCL
    else if (name == "pcl") backends.push_back(MakePclRegistration());
#endif
#if MOCAP_BENCH_WITH_OPEN3D
    else if (name == "open3d") backends.push_back(MakeOpen3dRegistration());
#endif
    else throw InputError("--backends", "no backend '" + name + "' in this build");
  }
  return backends;
}

std::string AllBackends() {
  std::string names = "segicp";  // ours first: the base of the ratios
#if MOCAP_BENCH_WITH_PCL
  names += ",pcl";
#endif
#if MOCAP_BENCH_WITH_OPEN3D
  names += ",open3d";
#endif
  return names;
}

int MakeLmo(const fs::path& dir) {
#if MOCAP_BENCH_WITH_LMO
  fs::create_directories(dir);
  const testing::BopDepthScene scene = testing::MakeBopDepthScene(fs::absolute(dir), {}, 7);
  std::printf("--name lmo --session %s --labels %s\n", scene.session.string().c_str(), scene.labels.string().c_str());
  return 0;
#else
  std::fprintf(stderr, "--make-lmo needs the tests' session fixture (configure with BUILD_TESTING=ON)\n");
  return 2;
#endif
}

/// Reads the arguments (see the top of this file); throws InputError on a malformed command line.
std::vector<Case> ParseCases(int argc, char** argv, fs::path* out, int* repeat, std::string* backends) {
  std::vector<Case> cases;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) throw InputError(flag, "needs a value");
    const std::string value = argv[++i];
    if (flag == "--out") *out = value;
    else if (flag == "--repeat") *repeat = std::stoi(value);
    else if (flag == "--backends") *backends = value;
    else if (flag == "--name") cases.push_back({value, {}, {}, {}, {}});
    else if (cases.empty()) throw InputError(flag, "comes before the first --name");
    else if (flag == "--session") cases.back().session = value;
    else if (flag == "--labels") cases.back().labels = value;
    else if (flag == "--objects") cases.back().objects = value;
    else if (flag == "--truth") cases.back().truth = value;
    else throw InputError(flag, "unknown flag");
  }
  for (const Case& c : cases)
    if (c.session.empty() || c.labels.empty()) throw InputError(c.name, "needs --session and --labels");
  if (cases.empty()) throw InputError("bench_validate_session", "no case given (--name N --session S --labels L ...)");
  return cases;
}

int Main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--make-lmo") return MakeLmo(argv[2]);
  fs::path out = fs::temp_directory_path() / "bench_validate_session";
  int repeat = 1;
  std::string names = AllBackends();
  const std::vector<Case> cases = ParseCases(argc, argv, &out, &repeat, &names);
  const auto backends = Backends(names);
  for (const Case& c : cases) {
    const pipeline::LabelRun labels = pipeline::LabelRun::Read(c.labels);
    const ReplayedSteps steps = ReplaySteps(c, labels);
    for (int r = 0; r < repeat; ++r) {
      std::vector<BackendRun> runs;
      for (const auto& backend : backends) {
        runs.push_back(RunBackend(c, labels, backend, out));
        std::fprintf(stderr, "%s %s: %.1f s\n", c.name.c_str(), runs.back().backend.c_str(), runs.back().wall_s);
      }
      PrintCase(c.name + ": " + c.session.string(), steps, runs);
    }
  }
  return 0;
}

}  // namespace
}  // namespace mocap::bench

int main(int argc, char** argv) {
  try {
    return mocap::bench::Main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_validate_session: %s\n", e.what());
    return 1;
  }
}
