#include "sim/record/sim_recorder.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <fstream>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "core/check.h"
#include "session/writer.h"
#include "sim/mesh_generator.h"
#include "sim/record/frame_render.h"
#include "sim/record/software_version.h"
#include "sim/record/truth_io.h"

namespace mocap::sim {
namespace {

namespace fs = std::filesystem;

SessionManifest SimManifest(const Scenario& scenario, const SimObjects& library, const RigCalibration& given) {
  SessionManifest manifest;
  manifest.source = "sim " + scenario.options.name;
  manifest.software_version = SimSoftwareVersion();
  CameraStreamInfo camera;
  camera.name = SimCameraName(scenario.options.sensor);
  camera.model = std::string(ToString(scenario.options.sensor));
  camera.serial = "sim";
  camera.color_camera = given.color_camera;
  camera.depth_camera = given.depth_camera;
  camera.depth_registered_to_color = scenario.options.sensor == SensorKind::kKinect1;
  camera.T_color_depth = given.T_color_depth;
  camera.depth_unit_m = 0.001;
  camera.camera_body = scenario.camera_body.name;
  camera.T_body_camera = given.T_cambody_camera;
  manifest.cameras.push_back(camera);
  TrackerStreamInfo tracker{kSimTrackerName, "sim-polaris", "sim", "tracker", {scenario.camera_body.name}};
  for (const ScenarioObject& object : scenario.objects) tracker.bodies.push_back(library.Find(object.name)->body.name);
  manifest.trackers.push_back(tracker);
  manifest.extra["sim"] = {{"scenario", scenario.options.name},
                           {"seed", scenario.options.seed},
                           {"recorded_by", "session writer (simulated frames written directly, not through the capture daemon)"}};
  return manifest;
}

int64_t WriteTrackerStreams(SessionWriter& writer, const std::vector<BodyStream>& streams) {
  int64_t written = 0;
  for (const BodyStream& stream : streams) {
    for (size_t k = 0; k < stream.samples.size(); ++k) {
      const PoseSample& s = stream.samples[k];
      TrackerRecord record;
      record.body = stream.body;
      record.status = s.status;
      record.device_frame = static_cast<int64_t>(k);
      record.stamp_ns = s.stamp_ns;
      record.T_frame_body = s.pose;
      record.rms_error_m = stream.measurements[k].fit_rms_m;
      writer.WriteTrackerSample(kSimTrackerName, record);
      ++written;
    }
  }
  return written;
}

cv::Mat ToBgr(const ColorImage& image) {
  cv::Mat bgr(image.height, image.width, CV_8UC3);
  for (int v = 0; v < image.height; ++v)
    for (int u = 0; u < image.width; ++u) {
      const Rgb8& p = image.at(u, v);
      bgr.at<cv::Vec3b>(v, u) = {p[2], p[1], p[0]};
    }
  return bgr;
}

cv::Mat ToMat(const DepthImage& depth) {
  return cv::Mat(depth.height, depth.width, CV_32FC1, const_cast<float*>(depth.data.data())).clone();
}


/// Hands frames to `write` in index order whatever order the workers finish them in.
class OrderedSink {
 public:
  template <typename Write>
  void Submit(int index, Write&& write) {
    std::unique_lock lock(mutex_);
    turn_.wait(lock, [&] { return next_ == index || failed_; });
    if (failed_) return;
    try {
      write();
    } catch (...) {
      failed_ = true;
      turn_.notify_all();
      throw;
    }
    ++next_;
    turn_.notify_all();
  }
  void Fail() {
    std::lock_guard lock(mutex_);
    failed_ = true;
    turn_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable turn_;
  int next_ = 0;
  bool failed_ = false;
};

struct FrameWriters {
  SessionWriter& session;
  std::string camera;
  FrameTap* tap = nullptr;
  fs::path truth_dir;
};

void WriteFrame(const SimFrame& frame, const FrameTruth& truth, FrameWriters& out) {
  const cv::Mat bgr = ToBgr(frame.color), depth = ToMat(frame.depth_m);
  CameraFrameRecord record;
  record.frame = frame.index;
  record.device_ticks = (truth.depth_time_ns * 60 + 500) / 1000;  // the Kinect's 60 MHz counter
  // The labelled image is the colour image: its exposure is the frame's time (Kinect v2 depth was taken
  // colour_delay_ms earlier; Kinect v1 at the same instant).
  record.stamp_ns = truth.color_time_ns;
  if (truth.depth_time_ns != truth.color_time_ns) record.depth_stamp_ns = truth.depth_time_ns;
  out.session.WriteCameraFrame(out.camera, record, bgr, depth);
  if (out.tap) out.tap->Add(bgr, depth, static_cast<uint64_t>(record.device_ticks), truth.depth_time_ns * 1e-9);
}

void WriteTruthInstances(const SimFrame& frame, const fs::path& truth_dir) {
  const LabelImage& ids = frame.true_instances;
  const cv::Mat mat(ids.height, ids.width, CV_16UC1, const_cast<uint16_t*>(ids.data.data()));
  const fs::path path = TruthInstancePng(truth_dir, frame.index);
  if (!cv::imwrite(path.string(), mat)) throw InputError(path.string(), "could not write the truth instance image");
}

/// Renders every frame on `threads` workers; returns the number of pixels without depth.
int64_t RenderAndWrite(const Scenario& scenario, const SimObjects& library, const SceneMeshes& meshes,
                       const SimulationTruth& truth, const RecordOptions& options, FrameWriters& out) {
  const int frames = static_cast<int>(truth.frames.size());
  const int threads = std::max(1, std::min(frames, options.threads > 0 ? options.threads
                                                                       : static_cast<int>(std::thread::hardware_concurrency())));
  std::atomic<int> next{0};
  std::atomic<int64_t> invalid{0};
  OrderedSink sink;
  Progress progress(options.progress, "sim record", frames, "frames");
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    try {
      FrameRenderer renderer(scenario, library, meshes, options.context);
      for (int i = next++; i < frames; i = next++) {
        const SimFrame frame = renderer.Render(truth.frames[static_cast<size_t>(i)], truth.true_calibration);
        invalid += frame.invalid_depth_pixels;
        WriteTruthInstances(frame, out.truth_dir);
        sink.Submit(i, [&] { WriteFrame(frame, truth.frames[static_cast<size_t>(i)], out); });
        progress.Advance();
      }
    } catch (...) {
      std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
      next = frames;
      sink.Fail();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(work);
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  return invalid;
}

void WriteTruth(const SimulationTruth& truth, const fs::path& dir) {
  WriteJsonFile(dir / "calibration.json", {{"true", ToJson(truth.true_calibration)},
                                           {"given", ToJson(truth.given_calibration)},
                                           {"injected", ToJson(truth.injected)},
                                           {"T_world_tracker", mocap::ToJson(truth.T_world_tracker)},
                                           {"occluder_instance_base", kOccluderInstanceBase}});
  std::ofstream poses(dir / "poses.jsonl");
  for (const FrameTruth& frame : truth.frames) poses << FrameTruthJson(frame).dump() << '\n';
  poses.close();
  if (!poses) throw InputError((dir / "poses.jsonl").string(), "could not write");
}


}  // namespace

std::string SimCameraName(SensorKind sensor) { return std::string(ToString(sensor)); }

void RecordOptions::check() const {
  if (out_dir.empty()) throw InputError("sim record", "no output folder given (--out)");
  if (threads < 0) throw InputError("sim record", "threads must be >= 0");
  // An empty regular file is "empty" to std::filesystem too, but it is not a folder to record into.
  if (fs::exists(out_dir) && (!fs::is_directory(out_dir) || !fs::is_empty(out_dir)))
    throw InputError(out_dir.string(), "exists and is not an empty folder; choose another --out or remove it");
  context.check();
}

RecordResult RecordSimulation(const Scenario& scenario, const SimObjects& library, const fs::path& library_dir,
                              const RecordOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  options.check();
  scenario.check(library, "scenario '" + scenario.options.name + "'");
  if (options.frame_tap && scenario.options.sensor != SensorKind::kKinect1)
    throw InputError("scenario '" + scenario.options.name + "'", "a frame tap (fakenect recording) takes Kinect v1 frames (sensor: kinect1)");
  RecordResult result;
  const SceneMotion motion(scenario);
  result.truth = ComputeTruth(motion, library);
  const std::vector<BodyStream> streams = SimulateTrackerStreams(motion, library);
  const RigCalibration& given = result.truth.given_calibration;
  const fs::path S = options.out_dir;
  auto writer = SessionWriter::Create(S, SimManifest(scenario, library, given));
  fs::path meshes_dir = library_dir;
  if (meshes_dir.empty()) {  // the built-in library: generate its meshes into the session
    meshes_dir = S / "meshes";
    WriteMeshLibrary(meshes_dir.string());
  }
  const SceneMeshes meshes = LoadSceneMeshes(scenario, library, meshes_dir.string());
  result.session_dir = S;
  result.library_dir = meshes_dir;
  result.truth_dir = S / "truth";
  fs::create_directories(result.truth_dir / "instance");
  if (options.frame_tap) options.frame_tap->Open(given.color_camera);
  // Truth first, and the caller's files (rig.yaml, objects.yaml: pipeline/record_stage.h) through
  // `options.before_close`: the session is marked complete (Close) only after everything.
  WriteTruth(result.truth, result.truth_dir);
  result.tracker_samples = WriteTrackerStreams(*writer, streams);
  FrameWriters out{*writer, SimCameraName(scenario.options.sensor), options.frame_tap, result.truth_dir};
  const int64_t invalid = RenderAndWrite(scenario, library, meshes, result.truth, options, out);
  if (options.frame_tap) options.frame_tap->Close();
  result.camera_name = SimCameraName(scenario.options.sensor);
  result.tracker_name = kSimTrackerName;
  result.camera_body = scenario.camera_body.name;
  if (options.before_close) options.before_close(result);
  writer->Close();
  result.frames = static_cast<int>(result.truth.frames.size());
  const double pixels = double(result.frames) * given.depth_camera.width * given.depth_camera.height;
  result.invalid_depth_fraction = pixels > 0 ? invalid / pixels : 0;
  for (const ScenarioObject& object : scenario.objects) result.body_of_object.push_back(library.Find(object.name)->body.name);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace mocap::sim
