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
// scene clouds (both replayed alone: per record the depth and instance PNGs read, the object's cloud cut
// once and thinned and indexed twice, as the tracking step and the label check do), and the rest (crops,
// scores, the observability analysis, filter and verdicts, writing the outputs). Accuracy: correct labels
// accepted (the cases' labels are correct: a simulated session's with its true calibration, LM-O's ground
// truth), SegICP success (the paper's criterion), and the estimate's position / rotation error against the
// truth (the simulated truth/poses.jsonl with --truth, else the label), median and p95.
//
// Usage:
//   bench_validate_session [--out DIR] [--repeat N] CASE...
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
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/check.h"
#include "pipeline/json_read.h"
#include "pipeline/label_run.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/scoring.h"
#include "pipeline/validate_stage.h"
#include "registration_backends.h"
#include "render/mesh.h"
#include "session/manifest.h"
#include "session/reader.h"
#include "validate/point_grid.h"
#if MOCAP_BENCH_WITH_LMO
#include "tests/validate/session_fixture.h"
#endif

namespace mocap::bench {
namespace {

namespace fs = std::filesystem;

double ThreadCpuS() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double ProcessCpuS() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

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
                         const ObservabilityOptions& options, double first_gate_m) const override {
    const double start = ThreadCpuS();
    IcpResult r = inner_->PointToPlane(crop, scene, T_init, options, first_gate_m);
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

/// Median and 95th percentile.
struct Spread {
  double median = 0, p95 = 0;
};
Spread SpreadOf(const std::vector<double>& v) { return {pipeline::Percentile(v, 50), pipeline::Percentile(v, 95)}; }

struct Row {
  std::string backend;
  int64_t records = 0, checked = 0, accepted = 0, estimated = 0;
  double success_rate = 0, wall_s = 0, cpu_s = 0, point_to_point_s = 0, point_to_plane_s = 0;
  Spread position_mm, rotation_deg;
};

/// The true T_camera_mesh per (simulated frame, object name), from a simulated session's truth/poses.jsonl.
using Truth = std::map<std::pair<int64_t, std::string>, Rigid3d>;
Truth ReadTruth(const fs::path& truth_dir) {
  Truth truth;
  const fs::path file = truth_dir / "poses.jsonl";
  for (const auto& [where, frame] : pipeline::ReadJsonLines(file))
    for (const nlohmann::json& o : frame.at("objects"))
      truth[{frame.at("index").get<int64_t>(), o.at("name").get<std::string>()}] = RigidFromJson(o.at("T_color_mesh"), where);
  return truth;
}

/// Estimate errors against the truth (or the label when there is none), over the records with an estimate.
void ScoreAgainstTruth(const SessionValidation& v, const Case& c, const pipeline::LabelRun& labels, Row* row) {
  std::map<std::tuple<std::string, int64_t, int>, int64_t> frame_of;  // (camera, index, instance) -> frame
  for (const pipeline::LabelRecord& r : labels.records) frame_of[{r.camera, r.index, r.instance}] = r.frame;
  const Truth truth = c.truth.empty() ? Truth() : ReadTruth(c.truth);
  std::vector<double> position_mm, rotation_deg;
  for (const RecordCheck& r : v.records) {
    row->accepted += r.check.verdict == Verdict::kAccept;
    if (!r.check.estimated) continue;
    ++row->estimated;
    Rigid3d reference = r.T_camera_object_label;
    if (!c.truth.empty()) {
      const auto it = truth.find({frame_of.at({r.camera, r.index, r.instance}), r.name});
      if (it == truth.end()) throw InputError(c.truth.string(), Str("has no pose of ", r.name, " at frame ", r.index));
      reference = it->second;
    }
    position_mm.push_back(1e3 * TranslationDistanceM(r.check.T_camera_object_segicp, reference));
    rotation_deg.push_back(RotationDistanceDeg(r.check.T_camera_object_segicp, reference));
  }
  row->position_mm = SpreadOf(position_mm);
  row->rotation_deg = SpreadOf(rotation_deg);
}

/// The session check's per-object scene voxel (session_check.cc OptionsFor: a large object gets coarser
/// crops and voxels so that its crops keep about CropOptions::max_points points).
double SceneVoxelOf(const ValidationObject& object, const ValidateOptions& o) {
  const Mesh mesh = LoadMesh(object.mesh_path.string(), object.unit_scale_to_m);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = Eigen::Vector3f::Constant(-1e30f);
  for (const Eigen::Vector3f& p : mesh.positions_m) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d size = (hi - lo).cast<double>().cwiseMax(0.0);
  const double face_m2 = std::max({size.x() * size.y(), size.y() * size.z(), size.x() * size.z()});
  return o.scene_voxel_m * std::max(1.0, std::sqrt(face_m2 / (o.crop.max_points * o.crop.pixel_m * o.crop.pixel_m)));
}

/// Reading the frames and making the scene clouds, replayed alone on one thread (CPU seconds).
struct ReplayedSteps {
  double io_s = 0, scene_cloud_s = 0;
};
ReplayedSteps ReplaySteps(const Case& c, const pipeline::LabelRun& labels) {
  const SessionReader session = SessionReader::Open(c.session);
  const std::vector<ValidationObject> objects =
      pipeline::ValidationObjectsOf(pipeline::ReadObjectLibrary(pipeline::FindObjectsFile(c.session, c.objects)));
  std::map<int, double> voxel_m;
  for (const ValidationObject& o : objects) voxel_m[o.id] = SceneVoxelOf(o, ValidateOptions());
  ReplayedSteps steps;
  for (const pipeline::LabelRecord& r : labels.records) {
    if (!r.has_pose || !session.frame(r.camera, r.index).depth_present) continue;
    double start = ThreadCpuS();
    const DepthImage depth_m = session.LoadDepth(r.camera, r.index);
    const cv::Mat png = cv::imread(labels.layout.InstancePng(r.camera, r.index).string(), cv::IMREAD_UNCHANGED);
    LabelImage mask(png.cols, png.rows);
    for (int v = 0; v < png.rows; ++v)
      for (int u = 0; u < png.cols; ++u) mask.at(u, v) = png.depth() == CV_8U ? png.at<uint8_t>(v, u) : png.at<uint16_t>(v, u);
    steps.io_s += ThreadCpuS() - start;
    start = ThreadCpuS();
    const PinholeCamera& camera = session.manifest().FindCamera(r.camera)->color_camera;
    const PointCloud cloud = DepthToPointsMasked(depth_m, camera, mask, static_cast<uint16_t>(r.instance));
    for (int twice = 0; twice < 2; ++twice) {
      const PointGrid grid(VoxelDownsample(cloud, voxel_m.at(r.object)));
      benchmark::DoNotOptimize(grid.size());
    }
    steps.scene_cloud_s += ThreadCpuS() - start;
  }
  return steps;
}

Row RunBackend(const Case& c, const pipeline::LabelRun& labels, const std::shared_ptr<const Registration>& backend,
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
  Row row;
  row.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  row.cpu_s = ProcessCpuS() - cpu_start;
  row.backend = std::string(timed->name());
  row.records = static_cast<int64_t>(v.records.size());
  row.checked = v.summary.records_checked;
  row.success_rate = v.summary.segicp_success_rate;
  row.point_to_point_s = timed->point_to_point_s();
  row.point_to_plane_s = timed->point_to_plane_s();
  ScoreAgainstTruth(v, c, labels, &row);
  return row;
}

void Print(const Case& c, const ReplayedSteps& steps, const std::vector<Row>& rows) {
  std::printf("\n%s: %s (labels %s)\n", c.name.c_str(), c.session.string().c_str(), c.labels.string().c_str());
  std::printf("| backend | records | records/s | wall s | CPU s | registration (p2p + p2plane) | frames read | scene clouds | rest "
              "| accepted | SegICP success | position mm median / p95 | rotation deg median / p95 |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const double registration_s = r.point_to_point_s + r.point_to_plane_s;
    const auto share = [&](double s) { return 100.0 * s / r.cpu_s; };
    std::printf("| %s | %lld | %.1f | %.2f | %.2f | %.0f %% (%.2f + %.2f s) | %.0f %% | %.0f %% | %.0f %% | %.1f %% | %.1f %% "
                "| %.2f / %.2f | %.3f / %.3f |\n",
                r.backend.c_str(), static_cast<long long>(r.records), r.records / r.wall_s, r.wall_s, r.cpu_s,
                share(registration_s), r.point_to_point_s, r.point_to_plane_s, share(steps.io_s), share(steps.scene_cloud_s),
                share(r.cpu_s - registration_s - steps.io_s - steps.scene_cloud_s),
                100.0 * static_cast<double>(r.accepted) / static_cast<double>(std::max<int64_t>(1, r.records)),
                100.0 * r.success_rate, r.position_mm.median, r.position_mm.p95, r.rotation_deg.median, r.rotation_deg.p95);
  }
  for (size_t i = 1; i < rows.size(); ++i)
    std::printf("%s / %s: wall %.2fx, CPU %.2fx, registration %.2fx\n", rows[i].backend.c_str(), rows[0].backend.c_str(),
                rows[i].wall_s / rows[0].wall_s, rows[i].cpu_s / rows[0].cpu_s,
                (rows[i].point_to_point_s + rows[i].point_to_plane_s) / (rows[0].point_to_point_s + rows[0].point_to_plane_s));
}

std::vector<std::shared_ptr<const Registration>> Backends() {
  std::vector<std::shared_ptr<const Registration>> backends = {nullptr};  // ours first: the ratios' base
#if MOCAP_BENCH_WITH_PCL
  backends.push_back(MakePclRegistration());
#endif
#if MOCAP_BENCH_WITH_OPEN3D
  backends.push_back(MakeOpen3dRegistration());
#endif
  return backends;
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
std::vector<Case> ParseCases(int argc, char** argv, fs::path* out, int* repeat) {
  std::vector<Case> cases;
  for (int i = 1; i < argc; ++i) {
    const std::string flag = argv[i];
    if (i + 1 >= argc) throw InputError(flag, "needs a value");
    const std::string value = argv[++i];
    if (flag == "--out") *out = value;
    else if (flag == "--repeat") *repeat = std::stoi(value);
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
  const std::vector<Case> cases = ParseCases(argc, argv, &out, &repeat);
  const auto backends = Backends();
  for (const Case& c : cases) {
    const pipeline::LabelRun labels = pipeline::LabelRun::Read(c.labels);
    const ReplayedSteps steps = ReplaySteps(c, labels);
    for (int r = 0; r < repeat; ++r) {
      std::vector<Row> rows;
      for (const auto& backend : backends) {
        rows.push_back(RunBackend(c, labels, backend, out));
        std::fprintf(stderr, "%s %s: %.1f s\n", c.name.c_str(), rows.back().backend.c_str(), rows.back().wall_s);
      }
      Print(c, steps, rows);
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
