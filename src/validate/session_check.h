#pragma once
// The session-level label check behind `mocaplabel validate` (docs/validation.md "Session check"): every
// labels.jsonl record with a pose is checked against the session's measured depth, cropped with the
// label's visible mask (the instance PNG) or with user masks, and gets a LabelCheck (SegICP pose,
// errors, success, label score, verdict). With user masks, their IoU / precision / recall against the
// label masks are measured too.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/progress.h"
#include "render/render_context.h"
#include "session/reader.h"
#include "validate/label_check.h"

namespace mocap {

/// An object of the label run: the id labels.jsonl calls `object`, and its mesh.
struct ValidationObject {
  int id = 0;
  std::string name;
  std::filesystem::path mesh_path;
  double unit_scale_to_m = 1.0;  ///< 0.001 for a mesh in millimetres
  /// A body of revolution: SegICP estimates are compared with the label modulo rotations about this axis.
  std::optional<SymmetryAxis> symmetry = std::nullopt;
  /// A time-of-flight camera's depth of its surface is pushed back along the ray (objects.yaml
  /// `tof_range_biased`: reflective): on such a camera its range is not judged (LeaveOutRange).
  bool tof_range_biased = false;
};

struct Mesh;

/// The run's options at one object's resolution: a large object (a table top) gets coarser crops and
/// scene voxels, so that its crops keep about CropOptions::max_points points (at 5 mm a table top's crop
/// had tens of thousands, and its checks took ten times a bottle's).
ValidateOptions OptionsForObject(const Mesh& mesh, ValidateOptions options);

/// What the pixel values of user masks (`--masks`) mean.
enum class MaskValues {
  kObjectId,    ///< the object id (objects.yaml `id`, labels.jsonl `object`, the label run's class PNGs)
  kInstanceId,  ///< the instance id (labels.jsonl `instance`, the label run's instance PNGs)
};

/// Where model crops come from.
enum class CropBackend {
  kSurface,   ///< SurfaceCropSource: CPU z-buffer over surface samples (parallel, no GL context)
  kRenderer,  ///< RenderedCropSource: the EGL renderer's depth of the mesh
};

struct SessionCheckOptions {
  /// The label run's folder, named in the outputs (the records and files come in a LabelRunView).
  std::filesystem::path labels_dir;
  /// User masks: DIR/<camera>/NNNNNN.png, or DIR/NNNNNN.png for a single-camera session; 8- or 16-bit
  /// single channel, 0 = background. Empty: the label run's instance PNGs.
  std::filesystem::path masks_dir;
  MaskValues mask_values = MaskValues::kObjectId;
  CropBackend crops = CropBackend::kSurface;
  /// Sequence mode (the default): one ObjectTracker per (camera, instance) runs over its frames in order,
  /// seeded by the label where it acquires (the first frame, after a failed step, every
  /// tracking.reacquire_every frames), and each label is checked against the tracker's measurement
  /// (CheckLabelWithTrack). Off: every record is checked on its own (CheckLabelInFrame, seeded as
  /// validate.check_seed says).
  bool track = true;
  int threads = 0;  ///< worker threads; 0 = OpenMP's default
  /// Only the records of frames [frame_begin, frame_end) are checked (a shard; -1: to the end), and of
  /// those only frames whose stream index is a multiple of `frame_stride` (1: every frame). The
  /// records with a pose of the other frames are left out of the result and of `records`; pose-less
  /// records are counted over all frames. For quick checks of long sessions (the demo).
  int frame_stride = 1;
  int64_t frame_begin = 0, frame_end = -1;
  /// Object ids whose records are left out like the skipped frames' (objects the check cannot verify).
  std::vector<int> skip_objects;
  /// Per camera, the depth-to-colour transform that replaces the session's (the label run's rig, from
  /// `calibrate depth-to-color`), for a camera whose depth is not registered to its colour (Kinect v2).
  std::map<std::string, Rigid3d> T_color_depth;
  ValidateOptions validate;
  RenderContextOptions context;  ///< for CropBackend::kRenderer
  ProgressSink* progress = nullptr;  ///< records checked / total (core/progress.h); not owned, may be null
  void check() const;            ///< throws InputError
};

/// Mask agreement of one record (user mask against the label's visible mask), pixels counted once.
struct SegmentationScore {
  double iou = 0.0, precision = 0.0, recall = 0.0;
};

/// The check of one labels.jsonl record.
struct RecordCheck {
  std::string camera;
  int64_t index = 0;      ///< frame index in the camera stream
  int64_t stamp_ns = 0;
  int object = 0;
  std::string name;
  int instance = 0;
  /// The label pose the depth is checked against: the labelled pose, moved to the depth's exposure where
  /// the frame's depth was taken apart from its colour (validate/depth_time.h; then label_shift_ns != 0).
  Rigid3d T_camera_object_label;
  int64_t depth_offset_ns = 0;  ///< the frame's depth exposure minus its colour exposure (0: together)
  int64_t label_shift_ns = 0;   ///< what the label was moved by: depth_offset_ns, or 0 = as labelled
  /// The pose as labelled, at the colour exposure, when the label was moved (label_shift_ns != 0): the
  /// label run drew the frame's masks there.
  std::optional<Rigid3d> T_camera_object_as_labelled;
  const Rigid3d& T_camera_object_of_masks() const {
    return T_camera_object_as_labelled ? *T_camera_object_as_labelled : T_camera_object_label;
  }
  LabelCheck check;
  std::string mode;                             ///< "frame", or the tracker phase ("acquisition", "tracking")
  std::optional<SegmentationScore> segmentation;  ///< with user masks, when either mask has pixels
  std::filesystem::path overlay;                  ///< the label run's overlay of the frame, if it wrote one
};

/// Median and spread of one quantity over records.
struct Stat {
  int64_t count = 0;
  double median = 0.0, p95 = 0.0, std = 0.0, max = 0.0;
};
Stat ComputeStat(std::vector<double> values);

/// The session-wide step's outcome (pipeline/session_wide.h runs it after CheckSession).
struct SessionWideSummary {
  bool ran = false;
  std::string why_not;                ///< when it did not run
  std::vector<std::string> findings;  ///< one line each; empty: nothing looks wrong session-wide
  int64_t records_flagged = 0;        ///< accepted records made suspect by a finding
};

struct ValidationSummary {
  int64_t records = 0;               ///< labels.jsonl records
  int64_t records_without_pose = 0;  ///< not checked: the label has no pose
  int64_t records_checked = 0;       ///< with a pose and usable input (an estimate was attempted)
  /// Paper's success criterion over records_checked (0 when none).
  double segicp_success_rate = 0.0;
  /// When records_checked is 0: why nothing was checked, one sentence naming the commonest reason (the
  /// rates and medians are then not measurements). Empty otherwise.
  std::string nothing_checked_why;
  /// Records whose depth was taken apart from their colour (Kinect v2): checked with the label moved to
  /// the depth's exposure, or at the colour's for want of a neighbouring label (validate/depth_time.h).
  int64_t labels_moved_to_depth_time = 0, labels_not_movable_to_depth_time = 0;
  std::map<std::string, int64_t> verdicts;  ///< accept / suspect / reject over records with a pose
  std::map<std::string, int64_t> reasons;   ///< reason codes over records with a pose
  Stat position_error_mm, rotation_axis_error_deg, rotation_angle_error_deg;  ///< over estimated records
  Stat label_score;
  bool has_segmentation = false;
  Stat iou, precision, recall;  ///< with user masks
  std::optional<SessionWideSummary> session_wide;  ///< absent where the step was not asked for
  double seconds = 0.0;
};

struct SessionValidation {
  std::vector<RecordCheck> records;  ///< records with a pose, in labels.jsonl order
  ValidationSummary summary;
};

/// What the check needs of a label run (pipeline/label_run.h reads runs and fills it): its records with a
/// pose, how many records it has in all, and where its per-frame files are.
struct LabelRunView {
  std::vector<RecordCheck> records;  ///< identity and label pose filled, checks empty
  int64_t total = 0;                 ///< every record, with a pose or not
  std::function<std::filesystem::path(const std::string& camera, int64_t index)> instance_png, overlay_png;
};

/// Checks every record of the label run against `session`. `objects` must cover every object id of
/// labels.jsonl. Bad frames (no depth, unreadable or missing masks, masks of the wrong size, too few
/// points) give suspect verdicts with reasons; throws InputError only for unusable inputs as a whole
/// (a record naming an unknown object or camera, a mesh that cannot be loaded).
SessionValidation CheckSession(const SessionReader& session, const std::vector<ValidationObject>& objects,
                               LabelRunView labels, const SessionCheckOptions& options);

/// Fills the summary from the record checks.
ValidationSummary Summarise(const std::vector<RecordCheck>& records, int64_t total_records);

}  // namespace mocap
