#pragma once
// `mocaplabel label`: every camera frame of a session, every object instance: the pose through the rig's
// chain of transforms, a render of all meshes, masks and statistics, written as files (label_output.h).
// Frames are processed in parallel, one EGL context per worker thread, and handed to a LabelSink; the
// pipeline's label run writer (pipeline/label_run.h) writes them into <out>.partial and publishes the
// run whole, so a crash or an error never leaves a partial output that looks complete.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "label/label_objects.h"
#include "label/label_output.h"
#include "label/pose_chain.h"
#include "label/rig.h"
#include "label/visibility.h"
#include "render/render_context.h"
#include "core/progress.h"
#include "render/renderer.h"
#include "session/reader.h"

namespace mocap {

struct LabelOptions {
  std::vector<std::string> cameras;  ///< cameras to label; empty = every camera of the session
  int threads = 0;                   ///< worker threads; 0 = one per core
  /// The frames labelled, by camera record index: [frame_begin, frame_end) of every camera (a shard);
  /// frame_end -1 = to the end.
  int64_t frame_begin = 0, frame_end = -1;
  FrameOutputOptions output;
  PoseChainOptions chain;
  VisibilityOptions visibility;
  /// Back faces are culled where that is exact (closed, outward meshes; per object, objects.yaml may
  /// override it).
  RendererOptions renderer{.back_face_culling = BackFaceCulling::kAuto};
  RenderContextOptions context;
  ProgressSink* progress = nullptr;  ///< frames done / total (core/progress.h); not owned, may be null
  /// A frame whose depth or colour file cannot be decoded (a corrupt PNG) is labelled without it and its
  /// records are flagged `unreadable_depth` / `unreadable_color` with the decoder's message; set this to
  /// stop the run with that error instead.
  bool stop_on_unreadable_image = false;
  void check() const;
};

/// Where the workers' time went, in seconds summed over workers: wall time, or the CPU time of the
/// worker threads themselves (llvmpipe's own rasteriser threads, if any, are not in the latter).
struct LabelStageSeconds {
  double render = 0;      ///< Renderer::Render (rasterisation, readback, the combined z-buffer)
  double read_depth = 0;  ///< loading the measured depth (and the colour for an overlay)
  double labels = 0;      ///< poses, masks and statistics, packing the masks, the labels.jsonl records
  double write = 0;       ///< encoding and writing the image files of the frame
  double total() const { return render + read_depth + labels + write; }
  LabelStageSeconds& operator+=(const LabelStageSeconds& o);
};

/// Whether an object's back faces were culled, and why.
struct ObjectCulling {
  std::string object;  ///< its name
  bool culled = false;
  /// "auto: closed and outward, ..." / "auto: 12 boundary edges" (AnalyzeClosure), or "always" / "never"
  /// when objects.yaml or the options chose.
  std::string reason;
};

struct LabelSummary {
  std::vector<std::string> cameras;  ///< labelled, in labels.jsonl's order
  int64_t frames = 0;             ///< camera records labelled (colour or depth present), in the frame range
  int64_t frames_skipped = 0;     ///< records whose image files are missing
  int64_t records = 0;            ///< labels.jsonl lines (frames x instances)
  int64_t records_with_pose = 0;
  int64_t frames_flagged = 0;     ///< frames with at least one flagged instance
  std::map<std::string, int64_t> flag_counts;
  double seconds = 0;             ///< wall clock of the whole run
  /// Wall clock until the first frame was started: meshes loaded, output folders made, a worker's EGL
  /// context created and the meshes uploaded (a fixed cost per run, whatever the session's length).
  double setup_seconds = 0;
  /// Wall clock from the first frame started to the last one written: frames / frames_seconds is the
  /// labelling rate a long session sees.
  double frames_seconds = 0;
  /// The process's CPU time (all threads) over that same span: what the frames cost, without the run's
  /// set-up except a later worker's that overlaps it.
  double frames_cpu_seconds = 0;
  double render_seconds = 0;      ///< summed over workers (= stages.render)
  LabelStageSeconds stages;       ///< wall time per stage, summed over workers
  LabelStageSeconds stages_cpu;   ///< CPU time of the worker threads per stage
  int threads = 0;                ///< worker threads used
  std::vector<ObjectCulling> culling;  ///< per object, in the objects' order
};

/// Labels the session's frames into `sink`. Throws InputError for a mesh that cannot be loaded or whose
/// extent does not fit its declared unit, an unknown camera, or an error of the sink (a failed write).
LabelSummary LabelSession(const SessionReader& session, const std::vector<LabelObject>& objects, const LabelRig& rig,
                          const LabelOptions& options, LabelSink& sink);

}  // namespace mocap
