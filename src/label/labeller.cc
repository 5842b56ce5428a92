#include "label/labeller.h"

#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <time.h>

#include "core/check.h"
#include "session/depth_in_color.h"
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

/// What one labelled frame adds to the summary.
struct FrameTally {
  bool labelled = false;  ///< false: outside the range, or its image files are missing
  int64_t records = 0, records_with_pose = 0;
  std::vector<std::string> flags;  ///< every instance's flags
};

/// One camera's frames; tallies[index] is filled when frame `index` is labelled.
struct CameraJob {
  std::string camera;
  std::unique_ptr<PoseChain> chain;
  DepthInColor depth;  ///< how its measured depth reaches the colour image
  int64_t begin = 0, end = 0;  ///< the frames labelled
  std::vector<FrameTally> tallies;
};

/// What a worker keeps between frames: its renderer, the uploaded meshes and the render buffers.
struct Worker {
  Renderer& renderer;
  const std::vector<MeshHandle>& handles;
  const std::vector<ColourHistogram>& mesh_colours;  ///< per object; empty unless the colour test on holes is on
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

/// Loads one image of a frame; an undecodable file gives an empty image and `flag` with the reason on
/// every record of the frame, unless the options ask to stop.
template <typename Image, typename Load>
Image LoadOrFlag(Load load, const char* flag, const LabelOptions& options, std::vector<InstanceResult>& results) {
  try {
    return load();
  } catch (const InputError& e) {
    if (options.stop_on_unreadable_image) throw;
    for (InstanceResult& r : results) {
      r.pose.flags.emplace_back(flag);
      r.pose.reason += (r.pose.reason.empty() ? "" : "; ") + std::string(e.what());
    }
    return Image();
  }
}

/// What the colour test on holes reads of a frame: its colour image and, per instance rendered, its
/// object's mesh colours; none when the colour image could not be read.
std::optional<HoleColours> HoleColoursOf(const cv::Mat& color, const std::vector<RenderItem>& items,
                                         const std::vector<size_t>& object_of_item,
                                         const std::vector<ColourHistogram>& mesh_colours) {
  if (color.empty()) return std::nullopt;
  MOCAP_CHECK(color.type() == CV_8UC3, "colour images are decoded as 8-bit BGR");
  HoleColours out{{color.cols, color.rows, color.data, color.step[0]}, {}};
  for (size_t k = 0; k < items.size(); ++k) out.mesh_colours[items[k].instance_id] = &mesh_colours[object_of_item[k]];
  return out;
}

/// Labels one frame with a worker's renderer, adding its time per stage to worker.seconds.
void LabelFrame(const SessionReader& session, const std::vector<LabelObject>& objects, Worker& worker, CameraJob& job,
                int64_t index, const LabelOptions& options, LabelSink& sink) {
  const CameraFrameEntry& entry = session.frame(job.camera, index);
  if (!entry.color_present && !entry.depth_present) return;
  StageClock clock;
  const PoseChain& chain = *job.chain;
  std::vector<InstanceResult> results(chain.instances().size());
  std::vector<RenderItem> items;
  std::vector<size_t> result_of_item, object_of_item;
  for (size_t i = 0; i < results.size(); ++i) {
    results[i].instance = &chain.instances()[i];
    results[i].pose = chain.Lookup(i, entry.record.stamp_ns);
    if (!results[i].pose.T_camera_mesh) continue;
    const auto object_index = static_cast<size_t>(results[i].instance->object - objects.data());
    items.push_back({worker.handles[object_index], *results[i].pose.T_camera_mesh, results[i].instance->instance_id});
    result_of_item.push_back(i), object_of_item.push_back(object_index);
  }
  clock.Lap(worker, &LabelStageSeconds::labels);  // the pose chain's lookups
  worker.renderer.Render(chain.camera(), items, worker.render);
  clock.Lap(worker, &LabelStageSeconds::render);
  // Kinect v2: registered into the colour image here; its holes (the baseline's occlusion shadows) are
  // judged by the visibility rule like any other.
  const DepthImage depth =
      entry.depth_present ? LoadOrFlag<DepthImage>([&] { return LoadDepthInColor(session, job.camera, index, job.depth); },
                                                   "unreadable_depth", options, results)
                          : DepthImage();
  const bool use_depth = !depth.data.empty();
  const bool overlay = options.output.write_overlay && entry.color_present;
  const bool colour_test = options.visibility.hole_colour && options.visibility.rule == VisibilityRule::kCombined &&
                           use_depth && entry.color_present;
  const cv::Mat color = overlay || colour_test
                            ? LoadOrFlag<cv::Mat>([&] { return session.LoadColor(job.camera, index); },
                                                  "unreadable_color", options, results)
                            : cv::Mat();
  clock.Lap(worker, &LabelStageSeconds::read_depth);
  const std::optional<HoleColours> colours =
      colour_test ? HoleColoursOf(color, items, object_of_item, worker.mesh_colours) : std::nullopt;
  const std::vector<ObjectLabels> labels = ComputeObjectLabels(worker.render, chain.camera(), use_depth ? &depth : nullptr,
                                                               options.visibility, colours ? &*colours : nullptr);
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
  sink.Write({job.camera, index, entry.record, worker.render, results, color, frame_masks, use_depth});
  clock.Lap(worker, &LabelStageSeconds::write);
  FrameTally& tally = job.tallies[static_cast<size_t>(index)];
  tally.labelled = true;
  for (const InstanceResult& r : results) {
    ++tally.records;
    tally.records_with_pose += r.pose.T_camera_mesh ? 1 : 0;
    tally.flags.insert(tally.flags.end(), r.pose.flags.begin(), r.pose.flags.end());
  }
}

int WorkerCount(const LabelOptions& options, size_t work_items) {
  const int threads =
      options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::min<int>(threads, static_cast<int>(std::max<size_t>(work_items, 1)));
}

/// Runs the workers, each with its own EGL context, over every (camera, frame). Rethrows the first error
/// of any worker after all have stopped. Fills the summary's stage times and thread count.
void RunWorkers(const SessionReader& session, const std::vector<LabelObject>& objects, const std::vector<Mesh>& meshes,
                std::vector<CameraJob>& jobs, const LabelOptions& options, LabelSink& sink, Clock::time_point start,
                LabelSummary& summary) {
  std::vector<ColourHistogram> mesh_colours;
  if (options.visibility.hole_colour)
    for (const Mesh& mesh : meshes) mesh_colours.push_back(MeshColours(mesh, options.visibility));
  std::vector<std::pair<size_t, int64_t>> work;
  for (size_t j = 0; j < jobs.size(); ++j)
    for (int64_t i = jobs[j].begin; i < jobs[j].end; ++i) work.emplace_back(j, i);
  Progress progress(options.progress, "label", static_cast<int64_t>(work.size()), "frames");
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
      Worker worker{renderer, handles, mesh_colours, {}, {}, {}};
      const Clock::time_point begin = Clock::now();
      const double begin_cpu = ProcessCpuSeconds();
      for (size_t w = next++; w < work.size() && !failed; w = next++) {
        LabelFrame(session, objects, worker, jobs[work[w].first], work[w].second, options, sink);
        progress.Advance();
      }
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

void Tally(const std::vector<CameraJob>& jobs, LabelSummary& summary) {
  for (const CameraJob& job : jobs) {
    for (int64_t i = job.begin; i < job.end; ++i) {
      const FrameTally& t = job.tallies[static_cast<size_t>(i)];
      if (!t.labelled) {
        ++summary.frames_skipped;
        continue;
      }
      ++summary.frames;
      summary.records += t.records;
      summary.records_with_pose += t.records_with_pose;
      for (const std::string& flag : t.flags) ++summary.flag_counts[flag];
      summary.frames_flagged += t.flags.empty() ? 0 : 1;
    }
  }
}

}  // namespace

LabelStageSeconds& LabelStageSeconds::operator+=(const LabelStageSeconds& o) {
  render += o.render, read_depth += o.read_depth, labels += o.labels, write += o.write;
  return *this;
}

void LabelOptions::check() const {
  if (threads < 0) throw InputError("label", "threads must be >= 0");
  if (frame_begin < 0 || (frame_end >= 0 && frame_end < frame_begin))
    throw InputError("label", Str("frame range [", frame_begin, ", ", frame_end, ") is not a range"));
  chain.check();
  visibility.check();
  renderer.check();
  context.check();
}

LabelSummary LabelSession(const SessionReader& session, const std::vector<LabelObject>& objects, const LabelRig& rig,
                          const LabelOptions& options, LabelSink& sink) {
  options.check();
  rig.check("rig");
  if (objects.empty()) throw InputError("objects", "no objects to label");
  CheckLabelObjects(objects, "objects");
  const auto start = Clock::now();
  const std::vector<Mesh> meshes = LoadMeshes(objects);
  std::vector<std::string> cameras = options.cameras;
  if (cameras.empty())
    for (const CameraStreamInfo& c : session.manifest().cameras) cameras.push_back(c.name);
  if (cameras.empty())
    throw InputError(session.dir().string(),
                     "the session has no camera stream, so there is nothing to label (a tracker-only recording or "
                     "import: Motive, PLUS and trajectory files carry poses, not images)");
  std::vector<CameraJob> jobs;
  for (const std::string& camera : cameras) {
    CameraJob job{camera, std::make_unique<PoseChain>(session, camera, objects, rig, options.chain), {}, 0, 0, {}};
    const LabelRigCamera* calibrated = rig.Find(camera);
    job.depth = DepthInColor::Of(*session.manifest().FindCamera(camera), job.chain->camera(),
                                 calibrated ? calibrated->T_color_depth : std::nullopt);
    const int64_t frames = session.frame_count(camera);
    job.begin = std::min(options.frame_begin, frames);
    job.end = options.frame_end < 0 ? frames : std::min(options.frame_end, frames);
    job.tallies.resize(static_cast<size_t>(frames));
    jobs.push_back(std::move(job));
  }
  sink.Begin(cameras, options.output);
  LabelSummary summary;
  summary.cameras = cameras;
  summary.culling = DecideCulling(objects, meshes, options.renderer.back_face_culling);
  RunWorkers(session, objects, meshes, jobs, options, sink, start, summary);
  Tally(jobs, summary);
  summary.seconds = SecondsSince(start);
  return summary;
}

}  // namespace mocap
