#include "label/labeller.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <fstream>
#include <mutex>
#include <thread>
#include <time.h>

#include "core/check.h"
#include "render/mesh.h"
#include "render/mesh_closure.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::vector<Mesh> LoadMeshes(const std::vector<LabelObject>& objects) {
  std::vector<Mesh> meshes;
  // LoadMesh refuses a missing or unreadable file and a mesh whose extent does not fit its unit.
  for (const LabelObject& o : objects) meshes.push_back(LoadMesh(o.mesh_path.string(), o.unit_scale_to_m));
  return meshes;
}

/// Decides once per object whether its back faces are culled (kAuto analyses the mesh), so the workers
/// upload with a fixed choice.
std::vector<ObjectCulling> DecideCulling(const std::vector<LabelObject>& objects, const std::vector<Mesh>& meshes,
                                         BackFaceCulling fallback) {
  std::vector<ObjectCulling> decisions;
  for (size_t i = 0; i < objects.size(); ++i) {
    const BackFaceCulling mode = objects[i].back_face_culling.value_or(fallback);
    ObjectCulling d{objects[i].name, mode == BackFaceCulling::kAlways, ToString(mode)};
    if (mode == BackFaceCulling::kAuto) {
      const MeshClosure closure = AnalyzeClosure(meshes[i]);
      d.culled = closure.culling_exact();
      d.reason = "auto: " + closure.Describe();
    }
    decisions.push_back(d);
  }
  return decisions;
}

fs::path PartialDir(const fs::path& out) {
  fs::path partial = out;
  partial += ".partial";
  return partial;
}

fs::path PrepareOutput(const fs::path& out, const std::vector<std::string>& cameras, const FrameOutputOptions& output) {
  if (fs::exists(out) && !fs::is_empty(out) && !fs::exists(out / "label_manifest.json"))
    throw InputError(out.string(), "exists and is not an earlier label output; choose another --out");
  const fs::path partial = PartialDir(out);
  fs::remove_all(partial);
  std::vector<std::string> subs = {"instance", "class"};
  if (output.write_depth) subs.push_back("depth");
  if (output.write_masks) subs.push_back("mask_bits");
  if (output.write_bop_masks) subs.insert(subs.end(), {"mask", "mask_visib", "mask_visib_depth"});
  if (output.write_overlay) subs.push_back("overlay");
  for (const std::string& camera : cameras)
    for (const std::string& sub : subs) fs::create_directories(partial / camera / sub);
  return partial;
}

/// One camera's frames; each frame's labels.jsonl lines land in lines[index] (empty: frame skipped).
struct CameraJob {
  std::string camera;
  std::unique_ptr<PoseChain> chain;
  bool depth_registered = false;
  std::vector<std::vector<nlohmann::json>> lines;
};

/// What a worker keeps between frames: its renderer, the uploaded meshes and the render buffers.
struct Worker {
  Renderer& renderer;
  const std::vector<MeshHandle>& handles;
  RenderOutput render;
  LabelStageSeconds wall, cpu;
};

double CpuSeconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
double ThreadCpuSeconds() { return CpuSeconds(CLOCK_THREAD_CPUTIME_ID); }
double ProcessCpuSeconds() { return CpuSeconds(CLOCK_PROCESS_CPUTIME_ID); }

/// Wall and thread-CPU clocks of one worker, read at each stage boundary.
struct StageClock {
  Clock::time_point wall = Clock::now();
  double cpu = ThreadCpuSeconds();

  /// Adds the time since the last lap to the stage (a member pointer of LabelStageSeconds).
  void Lap(Worker& worker, double LabelStageSeconds::*stage) {
    const auto wall_now = Clock::now();
    const double cpu_now = ThreadCpuSeconds();
    worker.wall.*stage += std::chrono::duration<double>(wall_now - wall).count();
    worker.cpu.*stage += cpu_now - cpu;
    wall = wall_now, cpu = cpu_now;
  }
};

/// Labels one frame with a worker's renderer, adding its time per stage to worker.seconds.
void LabelFrame(const SessionReader& session, const std::vector<LabelObject>& objects, Worker& worker, CameraJob& job,
                int64_t index, const LabelOptions& options, const fs::path& out) {
  const CameraFrameEntry& entry = session.frame(job.camera, index);
  if (!entry.color_present && !entry.depth_present) return;
  StageClock clock;
  const PoseChain& chain = *job.chain;
  std::vector<InstanceResult> results(chain.instances().size());
  std::vector<RenderItem> items;
  std::vector<size_t> result_of_item;
  for (size_t i = 0; i < results.size(); ++i) {
    results[i].instance = &chain.instances()[i];
    results[i].pose = chain.Lookup(i, entry.record.stamp_ns);
    if (!results[i].pose.T_camera_mesh) continue;
    const auto object_index = static_cast<size_t>(results[i].instance->object - objects.data());
    items.push_back({worker.handles[object_index], *results[i].pose.T_camera_mesh, results[i].instance->instance_id});
    result_of_item.push_back(i);
  }
  clock.Lap(worker, &LabelStageSeconds::labels);  // the pose chain's lookups
  worker.renderer.Render(chain.camera(), items, worker.render);
  clock.Lap(worker, &LabelStageSeconds::render);
  const bool use_depth = entry.depth_present && job.depth_registered;
  const DepthImage depth = use_depth ? session.LoadDepth(job.camera, index) : DepthImage();
  const bool overlay = options.output.write_overlay && entry.color_present;
  const cv::Mat color = overlay ? session.LoadColor(job.camera, index) : cv::Mat();
  clock.Lap(worker, &LabelStageSeconds::read_depth);
  const std::vector<ObjectLabels> labels =
      ComputeObjectLabels(worker.render, chain.camera(), use_depth ? &depth : nullptr, options.visibility);
  std::vector<PackedMasks> packed(options.output.write_masks ? labels.size() : 0);
  std::vector<PackedMasks*> stacked;
  for (size_t k = 0; k < result_of_item.size(); ++k) {
    InstanceResult& r = results[result_of_item[k]];
    r.labels = &labels[k];
    if (labels[k].stats.outside_image) r.pose.flags.push_back("outside_image");
    if (!options.output.write_masks) continue;
    packed[k] = PackMasks(labels[k].masks);
    r.packed = &packed[k];
    stacked.push_back(&packed[k]);
  }
  const cv::Mat frame_masks = StackMasks(stacked);
  clock.Lap(worker, &LabelStageSeconds::labels);
  WriteFrameImages(out, job.camera, index, worker.render, results, color, frame_masks, options.output);
  clock.Lap(worker, &LabelStageSeconds::write);
  auto& lines = job.lines[static_cast<size_t>(index)];
  for (const InstanceResult& r : results) lines.push_back(LabelRecord(job.camera, index, entry.record, r, use_depth));
  clock.Lap(worker, &LabelStageSeconds::labels);
}

int WorkerCount(const LabelOptions& options, size_t work_items) {
  const int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::min<int>(threads, static_cast<int>(std::max<size_t>(work_items, 1)));
}

/// Runs the workers, each with its own EGL context, over every (camera, frame). Rethrows the first error
/// of any worker after all have stopped. Fills the summary's stage times and thread count.
void RunWorkers(const SessionReader& session, const std::vector<LabelObject>& objects, const std::vector<Mesh>& meshes,
                std::vector<CameraJob>& jobs, const LabelOptions& options, const fs::path& out, Clock::time_point start,
                LabelSummary& summary) {
  std::vector<std::pair<size_t, int64_t>> work;
  for (size_t j = 0; j < jobs.size(); ++j)
    for (int64_t i = 0; i < static_cast<int64_t>(jobs[j].lines.size()); ++i) work.emplace_back(j, i);
  std::atomic<size_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex mutex;
  Clock::time_point first_frame = Clock::time_point::max(), last_frame = start;
  double first_frame_cpu = 0, last_frame_cpu = 0;  // the process's CPU clock at those two moments
  auto run = [&] {
    try {
      const auto context = RenderContext::Create(options.context);
      context->MakeCurrent();
      Renderer renderer(*context, options.renderer);
      std::vector<MeshHandle> handles;
      for (size_t i = 0; i < meshes.size(); ++i)
        handles.push_back(renderer.Upload(meshes[i], summary.culling[i].culled ? BackFaceCulling::kAlways
                                                                                : BackFaceCulling::kNever));
      Worker worker{renderer, handles, {}, {}, {}};
      const Clock::time_point begin = Clock::now();
      const double begin_cpu = ProcessCpuSeconds();
      for (size_t w = next++; w < work.size() && !failed; w = next++)
        LabelFrame(session, objects, worker, jobs[work[w].first], work[w].second, options, out);
      const Clock::time_point end = Clock::now();
      const double end_cpu = ProcessCpuSeconds();
      std::lock_guard lock(mutex);
      if (begin < first_frame) first_frame = begin, first_frame_cpu = begin_cpu;
      if (end > last_frame) last_frame = end, last_frame_cpu = end_cpu;
      summary.stages += worker.wall;
      summary.stages_cpu += worker.cpu;
    } catch (...) {
      std::lock_guard lock(mutex);
      if (!error) error = std::current_exception();
      failed = true;
    }
  };
  summary.threads = WorkerCount(options, work.size());
  std::vector<std::thread> pool;
  for (int t = 0; t < summary.threads; ++t) pool.emplace_back(run);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  summary.render_seconds = summary.stages.render;
  summary.setup_seconds = std::chrono::duration<double>(first_frame - start).count();
  summary.frames_seconds = std::chrono::duration<double>(last_frame - first_frame).count();
  summary.frames_cpu_seconds = last_frame_cpu - first_frame_cpu;
}

void WriteLines(const std::vector<CameraJob>& jobs, const fs::path& file, LabelSummary& summary) {
  std::ofstream jsonl(file);
  for (const CameraJob& job : jobs) {
    for (const auto& frame_lines : job.lines) {
      if (frame_lines.empty()) {
        ++summary.frames_skipped;
        continue;
      }
      ++summary.frames;
      bool flagged = false;
      for (const nlohmann::json& line : frame_lines) {
        jsonl << line.dump() << '\n';
        ++summary.records;
        if (line.contains("rvec")) ++summary.records_with_pose;
        for (const auto& flag : line["flags"]) {
          ++summary.flag_counts[flag.get<std::string>()];
          flagged = true;
        }
      }
      summary.frames_flagged += flagged ? 1 : 0;
    }
  }
  jsonl.close();
  if (!jsonl) throw InputError(file.string(), "could not write (disk full or not writable?)");
}

nlohmann::json StagesJson(const LabelStageSeconds& s) {
  return {{"render", s.render}, {"read_depth", s.read_depth}, {"labels", s.labels}, {"write", s.write}};
}

nlohmann::json CullingJson(const std::vector<ObjectCulling>& culling) {
  nlohmann::json j = nlohmann::json::array();
  for (const ObjectCulling& c : culling) j.push_back({{"object", c.object}, {"culled", c.culled}, {"reason", c.reason}});
  return j;
}

nlohmann::json SummaryJson(const LabelSummary& s, const SessionReader& session) {
  return {{"session", fs::absolute(session.dir()).string()},
          {"complete", s.complete},
          {"frames", s.frames},
          {"frames_skipped", s.frames_skipped},
          {"records", s.records},
          {"records_with_pose", s.records_with_pose},
          {"frames_flagged", s.frames_flagged},
          {"flag_counts", s.flag_counts},
          {"seconds", s.seconds},
          {"setup_seconds", s.setup_seconds},
          {"frames_seconds", s.frames_seconds},
          {"frames_cpu_seconds", s.frames_cpu_seconds},
          {"render_seconds", s.render_seconds},
          {"threads", s.threads},
          {"back_face_culling", CullingJson(s.culling)},
          {"stage_seconds", StagesJson(s.stages)},
          {"stage_cpu_seconds", StagesJson(s.stages_cpu)}};
}

/// Moves the finished output into place: the old output is removed only once the new one is whole.
void Publish(const fs::path& partial, const fs::path& out) {
  fs::remove_all(out);
  fs::rename(partial, out);
}

}  // namespace

LabelStageSeconds& LabelStageSeconds::operator+=(const LabelStageSeconds& o) {
  render += o.render, read_depth += o.read_depth, labels += o.labels, write += o.write;
  return *this;
}

void LabelOptions::check() const {
  if (out_dir.empty()) throw InputError("label", "no output folder given (--out)");
  if (threads < 0) throw InputError("label", "threads must be >= 0");
  chain.check();
  visibility.check();
  renderer.check();
  context.check();
}

LabelSummary LabelSession(const SessionReader& session, const std::vector<LabelObject>& objects, const Rig& rig,
                          const LabelOptions& options) {
  options.check();
  rig.check("rig");
  if (objects.empty()) throw InputError("objects", "no objects to label");
  CheckLabelObjects(objects, "objects");
  const auto start = Clock::now();
  const std::vector<Mesh> meshes = LoadMeshes(objects);
  std::vector<std::string> cameras = options.cameras;
  if (cameras.empty())
    for (const CameraStreamInfo& c : session.manifest().cameras) cameras.push_back(c.name);
  std::vector<CameraJob> jobs;
  for (const std::string& camera : cameras) {
    CameraJob job{camera, std::make_unique<PoseChain>(session, camera, objects, rig, options.chain), false, {}};
    job.depth_registered = session.manifest().FindCamera(camera)->depth_registered_to_color;
    job.lines.resize(static_cast<size_t>(session.frame_count(camera)));
    jobs.push_back(std::move(job));
  }
  const fs::path partial = PrepareOutput(options.out_dir, cameras, options.output);
  LabelSummary summary;
  summary.culling = DecideCulling(objects, meshes, options.renderer.back_face_culling);
  RunWorkers(session, objects, meshes, jobs, options, partial, start, summary);
  WriteLines(jobs, partial / "labels.jsonl", summary);
  summary.seconds = SecondsSince(start);
  summary.complete = true;
  summary.out_dir = options.out_dir;
  std::ofstream manifest(partial / "label_manifest.json");
  manifest << SummaryJson(summary, session).dump(2) << '\n';
  manifest.close();
  if (!manifest) throw InputError((partial / "label_manifest.json").string(), "could not write");
  Publish(partial, options.out_dir);
  return summary;
}

}  // namespace mocap
