#pragma once
// `mocaplabel sim record`: a simulated recording written as a real session (docs/session-format.md)
// with the session writer, plus what scoring and labelling need next to it (docs/simulation.md
// "Recording"):
//   S/manifest.json, S/cameras/..., S/trackers/...  the session (Kinect v1 colour + registered depth, or
//                                                   Kinect v2 colour + unregistered ToF depth; the
//                                                   tracker's bodies), calibration as *given*
//   S/meshes/                                       the built-in library's meshes (when no library is given)
//   S/truth/calibration.json                        true and given calibration, injected errors
//   S/truth/poses.jsonl                             per frame: true poses of every object (colour and depth frame)
//   S/truth/instance/<frame>.png                    uint16, colour image: library object id (occluders 65000 + k)
// Optionally every camera frame also goes to a FrameTap (frame_tap.h; e.g. a fakenect recording).
// Frames are rendered in parallel (one EGL context per worker) and written in frame order; the result
// is the same for any number of threads.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "render/render_context.h"
#include "sim/record/frame_tap.h"
#include "sim/sim_objects.h"
#include "sim/scenario.h"
#include "sim/truth.h"

namespace mocap::sim {

struct RecordOptions {
  std::filesystem::path out_dir;  ///< the session folder; must not exist or be empty
  int threads = 0;                ///< render workers; 0 = one per core
  /// Also fed every camera frame in order (Kinect v1 scenarios only); not owned, may be null.
  FrameTap* frame_tap = nullptr;
  RenderContextOptions context;
  ProgressSink* progress = nullptr;  ///< frames rendered / total (core/progress.h); not owned, may be null
  /// Called with the result (session, truth and library folders, names, truth filled) after the frames
  /// are written and before the session is closed: files written here (the pipeline's rig.yaml and
  /// objects.yaml of the given calibration) exist whenever the session is complete.
  std::function<void(const struct RecordResult&)> before_close;
  void check() const;  ///< throws InputError
};

struct RecordResult {
  int frames = 0;             ///< camera frames written
  int64_t tracker_samples = 0;
  double invalid_depth_fraction = 0;  ///< pixels without depth from the sensor model (shadows, edges, range)
  double seconds = 0;
  std::filesystem::path session_dir, truth_dir;
  std::filesystem::path library_dir;  ///< folder of the mesh files used
  SimulationTruth truth;
  std::vector<std::string> body_of_object;  ///< tracker body per scenario object
  std::string camera_name, tracker_name, camera_body;
};

/// Simulates and writes `scenario`. `library_dir` holds the library's mesh files (the folder of its
/// objects.yaml). Precondition: none; throws InputError for an invalid scenario, an unusable output
/// folder, a missing mesh or a failed write (the session then stays marked incomplete).
RecordResult RecordSimulation(const Scenario& scenario, const SimObjects& library,
                              const std::filesystem::path& library_dir, const RecordOptions& options);

/// The camera stream name of simulated sessions: "kinect1" or "kinect2".
std::string SimCameraName(SensorKind sensor);
inline constexpr const char* kSimTrackerName = "ndi";

}  // namespace mocap::sim
