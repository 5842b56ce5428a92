#include "validate/session_check.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>
#include <tuple>

#include "core/check.h"
#include "core/parallel_for.h"
#include "session/depth_in_color.h"
#include "session/image_io.h"
#include "render/mesh.h"
#include "session/records.h"
#include "validate/depth_time.h"
#include "validate/frame_visibility.h"
#include "validate/rendered_crop.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

std::string Stem(int64_t index) { return FrameFileStem(index); }

/// Everything one frame's records need, loaded once; a load failure is kept as a reason.
struct FrameInputs {
  DepthImage depth_m;
  std::string depth_problem;  ///< non-empty: why there is no depth
  VerdictReason depth_code = VerdictReason::kNoDepth;
  LabelImage label_mask;      ///< the label run's instance PNG
  std::string label_mask_problem;
  LabelImage user_mask;
  std::string user_mask_problem;
  fs::path overlay;
};

fs::path UserMaskPath(const SessionReader& session, const fs::path& dir, const std::string& camera, int64_t index) {
  const fs::path per_camera = dir / camera / (Stem(index) + ".png");
  if (fs::exists(per_camera) || session.manifest().cameras.size() > 1) return per_camera;
  return dir / (Stem(index) + ".png");
}

/// How `camera`'s depth reaches its colour image, the rig's calibrated T_color_depth in place of the
/// manifest's.
DepthInColor RegistrationOf(const CameraStreamInfo& camera, const SessionCheckOptions& options) {
  const auto calibrated = options.T_color_depth.find(camera.name);
  return DepthInColor::Of(camera, camera.color_camera,
                          calibrated != options.T_color_depth.end() ? std::optional<Rigid3d>(calibrated->second) : std::nullopt);
}

/// Where `camera`'s depth camera sits in its colour optical frame, the check's: the rays a time-of-flight
/// camera's range bias lies along start there.
Eigen::Vector3d TofCenterOf(const CameraStreamInfo& camera, const SessionCheckOptions& options) {
  return RegistrationOf(camera, options).T_color_depth.translation();
}

FrameInputs LoadFrame(const SessionReader& session, const LabelRunView& labels, const std::string& camera, int64_t index,
                      const SessionCheckOptions& options) {
  FrameInputs in;
  const CameraFrameEntry& entry = session.frame(camera, index);
  const CameraStreamInfo* info = session.manifest().FindCamera(camera);
  if (!entry.depth_present) {
    in.depth_problem = "frame has no depth image";
  } else {
    try {
      // A sensor whose depth camera sits beside its colour camera (Kinect v2): the labels are in the
      // colour image, so the depth is warped there first, as the labeller does.
      in.depth_m = LoadDepthInColor(session, camera, index, RegistrationOf(*info, options));
    } catch (const InputError& e) {
      in.depth_problem = e.what();
      in.depth_code = VerdictReason::kUnreadableInput;
    }
  }
  const auto load = [](const fs::path& path, LabelImage& image, std::string& problem) {
    try {
      image = ReadIdImage(path);
    } catch (const InputError& e) {
      problem = e.what();
    }
  };
  load(labels.instance_png(camera, index), in.label_mask, in.label_mask_problem);
  if (!options.masks_dir.empty())
    load(UserMaskPath(session, options.masks_dir, camera, index), in.user_mask, in.user_mask_problem);
  const fs::path overlay = labels.overlay_png(camera, index);
  if (fs::exists(overlay)) in.overlay = overlay;
  return in;
}

std::optional<SegmentationScore> ScoreMasks(const LabelImage& user, uint16_t user_value, const LabelImage& label,
                                            uint16_t label_value) {
  if (user.empty() || label.empty() || user.width != label.width || user.height != label.height) return std::nullopt;
  int64_t tp = 0, fp = 0, fn = 0;
  for (size_t i = 0; i < user.data.size(); ++i) {
    const bool predicted = user.data[i] == user_value, truth = label.data[i] == label_value;
    tp += predicted && truth;
    fp += predicted && !truth;
    fn += !predicted && truth;
  }
  if (tp + fp + fn == 0) return std::nullopt;  // the object is in neither mask: nothing to score
  const auto ratio = [](int64_t a, int64_t b) { return b > 0 ? static_cast<double>(a) / b : 0.0; };
  return SegmentationScore{ratio(tp, tp + fp + fn), ratio(tp, tp + fp), ratio(tp, tp + fn)};
}

/// The mask and value a record's cloud is cut with, or the reason there is none.
struct RecordMask {
  const LabelImage* mask = nullptr;
  uint16_t value = 0;
  std::string problem;
};
RecordMask MaskOf(const FrameInputs& in, const RecordCheck& r, const SessionCheckOptions& options) {
  if (options.masks_dir.empty()) return {&in.label_mask, static_cast<uint16_t>(r.instance), in.label_mask_problem};
  const int value = options.mask_values == MaskValues::kObjectId ? r.object : r.instance;
  return {&in.user_mask, static_cast<uint16_t>(value), in.user_mask_problem};
}

/// Input problems that stop a record before any cloud is cut (nullopt: usable).
std::optional<LabelCheck> InputProblem(const FrameInputs& in, const RecordMask& mask, const PinholeCamera& camera) {
  if (!in.depth_problem.empty()) return BadInputCheck(in.depth_code, in.depth_problem);
  if (!mask.problem.empty()) return BadInputCheck(VerdictReason::kUnreadableInput, mask.problem);
  return CheckFrameInput(in.depth_m, camera, *mask.mask, mask.value);
}

struct ObjectModel {
  ValidateOptions options;  ///< the run's, at this object's resolution (OptionsForObject)
  /// The same for a scene cloud the session check has already thinned to options.scene_voxel_m: the
  /// tracker and the check do not thin it again (that would leave it as it is, at a cost).
  ValidateOptions thinned_options;
  std::unique_ptr<CropSource> source;  ///< computes crops (z-buffer or renderer)
  std::unique_ptr<CachedCropSource> crops;  ///< each view's crop once, from `source`
  std::vector<ModelCrop> view_crops;  ///< for the view-sphere seed
  bool tof_range_biased = false;      ///< ValidationObject::tof_range_biased
  /// On this camera its range is biased along the ray: its position across the ray is the outline's.
  bool RangeBiasedOn(const CameraStreamInfo& camera) const { return tof_range_biased && camera.time_of_flight(); }
};

/// How the label run drew record r's mask, for the outline estimate.
MaskAtLabel DrawnAt(const RecordCheck& r, const ObjectModel& model, const CameraStreamInfo& camera,
                    const SessionCheckOptions& options) {
  return {r.T_camera_object_of_masks(), model.RangeBiasedOn(camera), TofCenterOf(camera, options)};
}

ObjectModel LoadModel(const ValidationObject& object, const SessionCheckOptions& options) {
  const Mesh mesh = LoadMesh(object.mesh_path.string(), object.unit_scale_to_m);
  ObjectModel model;
  model.tof_range_biased = object.tof_range_biased;
  model.options = OptionsForObject(mesh, options.validate);
  model.thinned_options = model.options;
  model.thinned_options.scene_voxel_m = 0;
  if (options.crops == CropBackend::kRenderer)
    model.source = std::make_unique<RenderedCropSource>(mesh, model.options.crop, options.context);
  else
    model.source = std::make_unique<SurfaceCropSource>(SurfaceCropSource::FromMesh(ToTriangleMesh(mesh), model.options.crop));
  model.crops = std::make_unique<CachedCropSource>(*model.source, model.options.crop_cache);
  if (model.options.check_seed == AcquisitionSeed::kViewSphere && !options.track)
    model.view_crops = MakeViewSphereCrops(*model.crops, model.options.acquisition);
  return model;
}

/// The records' objects, each loaded once; the surface samplings run in parallel (a table's took a
/// tenth of a second), the renderer's crop sources one after another on its one context.
std::map<int, ObjectModel> LoadModels(const std::vector<ValidationObject>& objects,
                                      const std::vector<RecordCheck>& records, const SessionCheckOptions& options) {
  std::vector<const ValidationObject*> wanted;
  for (const RecordCheck& r : records) {
    if (std::ranges::any_of(wanted, [&](const ValidationObject* o) { return o->id == r.object; })) continue;
    const auto it = std::find_if(objects.begin(), objects.end(), [&](const auto& o) { return o.id == r.object; });
    if (it == objects.end())
      throw InputError(Str("labels.jsonl object ", r.object), "not among the objects given (pass the --objects the label run used)");
    wanted.push_back(&*it);
  }
  std::vector<ObjectModel> loaded(wanted.size());
  const int threads = options.crops == CropBackend::kRenderer ? 1 : options.threads;
  ParallelFor(static_cast<int>(wanted.size()), threads, [&](int i) { loaded[i] = LoadModel(*wanted[i], options); });
  std::map<int, ObjectModel> models;
  for (size_t i = 0; i < wanted.size(); ++i) models.emplace(wanted[i]->id, std::move(loaded[i]));
  return models;
}

/// Groups record indices by key, each group in labels.jsonl order.
template <typename Key>
std::vector<std::vector<size_t>> GroupBy(const std::vector<RecordCheck>& records, Key key) {
  std::map<decltype(key(records.front())), std::vector<size_t>> groups;
  for (size_t i = 0; i < records.size(); ++i) groups[key(records[i])].push_back(i);
  std::vector<std::vector<size_t>> out;
  for (auto& [k, g] : groups) out.push_back(std::move(g));
  return out;
}

void Score(const FrameInputs& in, const SessionCheckOptions& options, RecordCheck& r) {
  r.overlay = in.overlay;
  if (options.masks_dir.empty()) return;
  const RecordMask mask = MaskOf(in, r, options);
  r.segmentation = ScoreMasks(*mask.mask, mask.value, in.label_mask, static_cast<uint16_t>(r.instance));
}

/// One frame's records, each checked on its own.
void CheckFrame(const SessionReader& session, const LabelRunView& labels, const std::map<int, ObjectModel>& models,
                const SessionCheckOptions& options, std::vector<RecordCheck>& records, const std::vector<size_t>& group) {
  const RecordCheck& first = records[group.front()];
  const FrameInputs in = LoadFrame(session, labels, first.camera, first.index, options);
  const CameraStreamInfo& info = *session.manifest().FindCamera(first.camera);
  const PinholeCamera& camera = info.color_camera;
  for (size_t i : group) {
    RecordCheck& r = records[i];
    const RecordMask mask = MaskOf(in, r, options);
    const ObjectModel& model = models.at(r.object);
    r.mode = "frame";
    if (!in.depth_problem.empty() || !mask.problem.empty())
      r.check = *InputProblem(in, mask, camera);
    else {
      const MaskAtLabel drawn = DrawnAt(r, model, info, options);
      r.check = CheckLabelInFrame(in.depth_m, camera, *mask.mask, mask.value, r.T_camera_object_label, *model.crops,
                                  model.view_crops, model.options, options.masks_dir.empty() ? &drawn : nullptr);
    }
    Score(in, options, r);
  }
}

/// The camera's depth resolution at the estimate's analysis centre: the depth camera's own pixel (a
/// Kinect v2's depth has a third of its colour camera's pixels across) and its step at that range.
DepthResolution ResolutionAt(const CameraStreamInfo& camera, const LabelCheck& c) {
  const double z_m = (c.T_camera_object_segicp * c.observability.center_object).z();
  const PinholeCamera& depth = camera.depth_camera.fx > 0 ? camera.depth_camera : camera.color_camera;
  return {z_m / depth.fx, camera.depth_step_m(z_m)};
}

/// An accepted check whose difference lies well inside the accept bounds (tracking.confirm_fraction).
bool ClearAgreement(const LabelCheck& c, const ValidateOptions& options) {
  if (c.verdict != Verdict::kAccept) return false;
  const ObservedDifference judged = JudgedDifference(c);
  const double fraction = options.tracking.confirm_fraction;
  return judged.position_mm <= fraction * c.accept_position_mm && judged.rotation_deg <= fraction * c.accept_rotation_deg;
}

/// One record through its instance's tracker, with the frame's inputs already read.
void CheckTracked(const FrameInputs& in, const SessionReader& session, const ObjectModel& model,
                  const SessionCheckOptions& options, ObjectTracker& tracker, int64_t& last_stamp_ns, RecordCheck& r) {
  const CameraStreamInfo& info = *session.manifest().FindCamera(r.camera);
  const PinholeCamera& camera = info.color_camera;
  const RecordMask mask = MaskOf(in, r, options);
  if (auto bad = InputProblem(in, mask, camera)) {
    r.check = *bad;  // the tracker skips the frame: its filter bridges the gap at the next one
    r.mode = "skipped";
    return;
  }
  const bool seed_from_label = model.options.check_seed == AcquisitionSeed::kLabel;
  // Cross-checks at fixed frame indices: a shard starting at such a frame checks as the whole run does.
  const int every = model.options.tracking.reacquire_every;
  // The mask less what the depth shows in front (a hand), its cloud thinned here once for the tracker and
  // the check (model.thinned_options), and its crops as this frame sees them.
  const ObjectInFrame object(in.depth_m, camera, *mask.mask, mask.value, r.T_camera_object_label, *model.crops,
                             model.options);
  const PointCloud scene = VoxelDownsample(object.SceneCloud(), model.options.scene_voxel_m);
  // Without a tracked camera body the camera is taken as static (motion all in the object).
  const InterpolatedPose camera_pose = session.CameraPoseAtFrame(r.camera, r.index);
  const int64_t stamp_ns = std::max(r.stamp_ns, last_stamp_ns + 1);
  last_stamp_ns = stamp_ns;
  // The label seeds the acquisitions (the first frame, after a loss, the periodic cross-check), as in the
  // per-frame mode.
  const CropSource& frame_model = object.crops();
  const CropSource* label_model = object.label_crops();
  const TrackStep step = tracker.Step(scene, camera_pose.ok() ? *camera_pose.pose : Rigid3d(), stamp_ns,
                                      seed_from_label ? &r.T_camera_object_label : nullptr, &frame_model,
                                      every > 0 && r.index % every == 0);
  // The label run's masks are the models' silhouettes at the labels: the outline estimate reads them so.
  const OutlineFrame outline_frame = object.Outline(DrawnAt(r, model, info, options));
  const OutlineFrame* outline = options.masks_dir.empty() ? &outline_frame : nullptr;
  r.check = CheckLabelWithTrack(scene, r.T_camera_object_label, frame_model, step, model.thinned_options, label_model,
                                outline);
  r.mode = std::string(ToString(step.mode));
  // A tracking step is the fast path to a clear agreement; a disagreement or a close call is evidence
  // only from a full acquisition (a track can settle a few millimetres off while a carried object
  // moves, or keep a few degrees of its start about a weakly constrained axis), so it is checked
  // again as the per-frame mode does.
  if (step.mode == TrackMode::kTracking && seed_from_label && !ClearAgreement(r.check, model.options)) {
    // The frame's cloud, already thinned, and its crops as above: what CheckLabelInFrame would make again.
    r.check = CheckLabel(scene, r.T_camera_object_label, frame_model, model.view_crops, model.thinned_options,
                         label_model, outline);
    r.mode = "recheck";
  }
  r.check.occluder_pixels = object.occluder_pixels();
}

/// Frames shared by the jobs that check one stretch's instances apart: each frame is read by the first job
/// that needs it (the others wait for it) and dropped once all of its records are checked, so splitting a
/// stretch into jobs per instance reads no frame twice (reading them once per job cost the balance it won).
class SharedFrames {
 public:
  /// `share` false: every Get reads its frame afresh (jobs that run through a whole session apart
  /// would otherwise hold every frame until the last of them passes it).
  SharedFrames(const std::vector<RecordCheck>& records, bool share) : share_(share) {
    if (share_)
      for (const RecordCheck& r : records) ++entries_[{r.camera, r.index}].pending;
  }
  /// The inputs of record r's frame; `load` reads them.
  template <typename Load>
  std::shared_ptr<const FrameInputs> Get(const RecordCheck& r, Load load) {
    if (!share_) return std::make_shared<const FrameInputs>(load());
    Entry* entry = nullptr;
    {
      std::lock_guard lock(mutex_);
      entry = &entries_.at({r.camera, r.index});
    }
    std::call_once(entry->once, [&] { entry->frame = std::make_shared<const FrameInputs>(load()); });
    return entry->frame;  // not reset before this record's Done
  }
  /// Record r is checked: its frame is dropped after the last of its records.
  void Done(const RecordCheck& r) {
    if (!share_) return;
    std::lock_guard lock(mutex_);
    Entry& entry = entries_.at({r.camera, r.index});
    if (--entry.pending == 0) entry.frame.reset();
  }

 private:
  struct Entry {
    int pending = 0;  ///< records of the frame not yet checked
    std::once_flag once;
    std::shared_ptr<const FrameInputs> frame;
  };
  const bool share_;
  std::mutex mutex_;
  std::map<std::pair<std::string, int64_t>, Entry> entries_;  // nodes stay put: Get keeps a pointer
};

/// A group of one camera's records in frame order, each instance through its own tracker; a frame's inputs
/// are read once for all of its records (`frames`).
void CheckTracks(const SessionReader& session, const LabelRunView& labels, const std::map<int, ObjectModel>& models,
                 const SessionCheckOptions& options, SharedFrames& frames, std::vector<RecordCheck>& records,
                 std::vector<size_t> group) {
  std::stable_sort(group.begin(), group.end(), [&](size_t a, size_t b) { return records[a].index < records[b].index; });
  struct Track {
    ObjectTracker tracker;
    int64_t last_stamp_ns = 0;
  };
  std::map<int, Track> tracks;  // by instance
  std::shared_ptr<const FrameInputs> in;
  for (size_t n = 0; n < group.size(); ++n) {
    RecordCheck& r = records[group[n]];
    if (n == 0 || r.index != records[group[n - 1]].index)
      in = frames.Get(r, [&] { return LoadFrame(session, labels, r.camera, r.index, options); });
    const ObjectModel& model = models.at(r.object);
    // Built on a track's first record only: a tracker's construction bounds the whole surface model.
    auto it = tracks.find(r.instance);
    if (it == tracks.end()) it = tracks.emplace(r.instance, Track{ObjectTracker(*model.crops, model.thinned_options)}).first;
    Track& track = it->second;
    CheckTracked(*in, session, model, options, track.tracker, track.last_stamp_ns, r);
    Score(*in, options, r);
    frames.Done(r);
  }
}

}  // namespace

ValidateOptions OptionsForObject(const Mesh& mesh, ValidateOptions o) {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = Eigen::Vector3f::Constant(-1e30f);
  for (const Eigen::Vector3f& p : mesh.positions_m) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Eigen::Vector3d size = (hi - lo).cast<double>().cwiseMax(0.0);
  const double largest_face_m2 = std::max({size.x() * size.y(), size.y() * size.z(), size.x() * size.z()});
  const double scale = std::max(1.0, std::sqrt(largest_face_m2 / (o.crop.max_points * o.crop.pixel_m * o.crop.pixel_m)));
  o.crop.pixel_m *= scale;
  o.scene_voxel_m *= scale;
  o.crop_cache.normal_radius_m *= scale;
  o.observability.normal_radius_m *= scale;
  return o;
}

void SessionCheckOptions::check() const {
  if (labels_dir.empty()) throw InputError("validate", "no label folder given (--labels)");
  if (!masks_dir.empty() && !fs::is_directory(masks_dir))
    throw InputError(masks_dir.string(), "mask folder does not exist (--masks)");
  if (threads < 0) throw InputError("validate", "threads must be >= 0");
  if (frame_stride < 1) throw InputError("validate", "frame stride must be >= 1");
  if (frame_begin < 0 || (frame_end >= 0 && frame_end < frame_begin))
    throw InputError("validate", Str("frame range [", frame_begin, ", ", frame_end, ") is not a range"));
  validate.check();
  context.check();
}

SessionValidation CheckSession(const SessionReader& session, const std::vector<ValidationObject>& objects,
                               LabelRunView labels, const SessionCheckOptions& options) {
  options.check();
  MOCAP_CHECK(labels.instance_png && labels.overlay_png, "a label run view without its file paths");
  const auto start = std::chrono::steady_clock::now();
  std::vector<RecordCheck>& records = labels.records;
  // Before any record is left out, so that a left-out frame's label still brackets its neighbours' depth.
  MoveLabelsToDepthTime(session, records);
  const auto skipped = std::erase_if(records, [&](const RecordCheck& r) {
    return r.index % options.frame_stride != 0 || std::ranges::count(options.skip_objects, r.object) > 0 ||
           r.index < options.frame_begin || (options.frame_end >= 0 && r.index >= options.frame_end);
  });
  labels.total -= static_cast<int64_t>(skipped);
  for (const RecordCheck& r : records) {
    if (!session.manifest().FindCamera(r.camera))
      throw InputError(Str("labels.jsonl camera \"", r.camera, "\""), "not in the session; is it the session the labels came from?");
    if (r.index < 0 || r.index >= session.frame_count(r.camera))
      throw InputError(Str("labels.jsonl ", r.camera, " frame ", r.index), "beyond the session's frames");
  }
  SessionValidation out;
  if (!records.empty()) {
    const std::map<int, ObjectModel> models = LoadModels(objects, records, options);
    Progress progress(options.progress, "validate", static_cast<int64_t>(records.size()), "records");
    if (options.track) {
      // One tracker per instance and stretch between cross-checks: a tracker started at a cross-check
      // frame checks as the continued one does (see CheckTracked), and the stretches keep every core
      // busy where one instance's track would outlast the others. Each instance's stretch is a job of its
      // own (smaller jobs end more evenly on few cores), in stretch order, sharing
      // the stretch's frames; without cross-checks each instance is a job over the whole session.
      const int every = options.validate.tracking.reacquire_every;
      const auto groups = GroupBy(records, [every](const RecordCheck& r) {
        return std::make_tuple(r.camera, every > 0 ? r.index / every : int64_t{0}, r.instance);
      });
      SharedFrames frames(records, every > 0);
      ParallelFor(static_cast<int>(groups.size()), options.threads, [&](int g) {
        CheckTracks(session, labels, models, options, frames, records, groups[g]);
        progress.Advance(static_cast<int64_t>(groups[g].size()));
      });
    } else {
      const auto groups = GroupBy(records, [](const RecordCheck& r) { return std::make_pair(r.camera, r.index); });
      ParallelFor(static_cast<int>(groups.size()), options.threads, [&](int g) {
        CheckFrame(session, labels, models, options, records, groups[g]);
        progress.Advance(static_cast<int64_t>(groups[g].size()));
      });
    }
  }
  for (RecordCheck& r : records) {
    const auto it = std::find_if(objects.begin(), objects.end(), [&](const auto& o) { return o.id == r.object; });
    if (it == objects.end()) continue;
    const CameraStreamInfo* camera = session.manifest().FindCamera(r.camera);
    if (camera) ApplyDepthResolution(ResolutionAt(*camera, r.check), options.validate, &r.check);
    if (it->symmetry) ApplySymmetry(r.T_camera_object_label, *it->symmetry, options.validate, &r.check);
    if (it->tof_range_biased && camera && camera->time_of_flight())
      LeaveOutRange(r.T_camera_object_label, TofCenterOf(*camera, options), options.validate, &r.check);
  }
  out.summary = Summarise(records, labels.total);
  if (records.empty() && skipped > 0)
    out.summary.nothing_checked_why = Str("all ", skipped, " label records with a pose were left out (by frame range, frame stride ",
                                          options.frame_stride, " or ", options.skip_objects.size(), " objects left out)");
  out.summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.records = std::move(records);
  return out;
}

}  // namespace mocap
