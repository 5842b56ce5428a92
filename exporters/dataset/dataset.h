#pragma once
// What every exporter reads (docs/export.md): sessions with their label runs and, where there is one,
// their validation runs, read through the pipeline's run readers (pipeline/label_run.h,
// validation_run.h); the frames and object instances that passed the filters, and the split each frame
// went to. The writers (bop_writer.h, coco_writer.h, segpairs_writer.h, tum_writer.h) see only this.
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"
#include "label/object_labels.h"
#include "pipeline/label_run.h"
#include "pipeline/object_library.h"
#include "session/reader.h"

namespace mocap::exporters {

/// One session to export, with its label run and (optionally) its validation run.
struct ExportInput {
  std::filesystem::path session_dir;
  std::filesystem::path labels_dir;      ///< empty: SESSION/labels
  std::filesystem::path validation_dir;  ///< empty: SESSION/validation when it holds a finished run
  bool ignore_validation = false;        ///< export as if there were no validation run (all unchecked)
};

/// One camera of one session: a scene of the dataset (a BOP scene folder).
struct ExportScene {
  int scene_id = 0;                   ///< 1-based, in input order, then camera order
  std::string name;                   ///< "<session folder name>/<camera>"
  std::filesystem::path session_dir;  ///< absolute
  std::filesystem::path labels_dir, validation_dir;  ///< absolute; validation_dir empty when none
  pipeline::LabelRunLayout labels;
  std::string camera;                 ///< camera stream name in the session
  std::string camera_model;           ///< the manifest's model: kinect1, kinect2, ...
  PinholeCamera color_camera;         ///< the intrinsics the labels were made with (the rig's or the session's)
  PinholeCamera depth_camera;         ///< the depth image's own camera (equal to color_camera when registered)
  Rigid3d T_color_depth;              ///< depth optical frame into the colour optical frame
  bool depth_registered_to_color = true;
  double depth_unit_m = 0.001;        ///< metres per depth image unit
  std::shared_ptr<const SessionReader> session;  ///< the session, open
};

/// One object instance of an exported frame.
struct ExportInstance {
  pipeline::LabelRecord record;  ///< the label run's record (pose, boxes, pixel counts, mask location)
  std::string verdict;           ///< the validator's: accept, suspect or reject; "" when not checked
  std::string verdict_reason;    ///< its reason ("" when none)
  bool has_check = false;        ///< a validation record exists for it
  /// Known not to be in the frame: its body is never reported in the session (an object of the library
  /// that this session does not hold), or its poses are known per frame (a BOP import: a tracker in the
  /// camera's frame) and this frame has none. Not a bad label; the filters leave it out silently.
  bool absent = false;
  /// The validator's residuals, when checked.
  double check_error_mm = -1, check_error_deg = -1;
};

/// One exported camera frame.
struct ExportFrame {
  size_t scene = 0;                       ///< index into Dataset::scenes
  int64_t index = 0;                      ///< camera record index in the session (labels.jsonl `index`)
  int64_t frame = 0;                      ///< the camera's own frame number
  int64_t stamp_ns = 0;                   ///< host clock (session time)
  int im_id = 0;                          ///< BOP im_id: the camera record index, stable whatever the filters keep
  std::filesystem::path color_path, depth_path;  ///< "" when the recording has none
  /// The colour camera in the tracker's frame at the frame's time (rig latency applied), when the
  /// camera is tracked.
  std::optional<Rigid3d> T_tracker_camera;
  std::vector<ExportInstance> instances;  ///< the instances kept, in labels.jsonl order
  std::string split;                      ///< train, val or test
};

struct Dataset {
  /// Every object of every input's object library, merged: one id per name, stable across sessions.
  pipeline::ObjectLibrary objects;
  std::vector<ExportScene> scenes;
  std::vector<ExportFrame> frames;  ///< scene by scene, in index order
  /// Provenance: every input run and file the dataset was made from (role, path).
  std::vector<std::pair<std::string, std::filesystem::path>> inputs;

  const ExportScene& scene_of(const ExportFrame& frame) const { return scenes.at(frame.scene); }
  /// The splits present, in the order train, val, test.
  std::vector<std::string> splits() const;
};

/// What a writer wrote, for the export summary.
struct WriteSummary {
  std::string format;
  int64_t images = 0;       ///< frames written
  int64_t annotations = 0;  ///< object instances written
  int64_t files = 0;        ///< files created (hard links included)
  std::map<std::string, int64_t> images_per_split, annotations_per_split;
  std::vector<std::string> notes;  ///< one line each (e.g. "colour copied: the file system has no hard links")
};

/// The three masks of each of the frame's instances (parallel to frame.instances), read from the label
/// run's packed mask file of the frame (label/mask_file.h), decoded once. An instance that covers no
/// pixel gets empty masks (an empty rect). Throws InputError naming the file when the label run wrote
/// no masks (`label --no-masks`) or the file does not hold the records' crops.
std::vector<ObjectMasks> ReadFrameMasks(const ExportScene& scene, const ExportFrame& frame);

/// The visible mask exporters publish: the measured-depth rule (BOP's mask_visib) when the label run had
/// measured depth for the frame, else the model z-buffer's.
const std::vector<uint8_t>& VisibleMask(const ObjectMasks& masks, const pipeline::LabelRecord& record);
// A full-image 0/255 mask of a cropped one: FullMaskImage (label/label_output.h). A recorded image
// placed in a dataset: LinkOrCopyFile (session/durable_file.h).

/// The frame's measured depth in metres (CV_32FC1, 0 = no depth) in the colour camera's image: as
/// recorded when the depth is registered to the colour camera, else each depth pixel reprojected into
/// the colour image through T_color_depth, nearest surface kept (Kinect v2). Empty when the frame has no
/// depth. Throws InputError naming the file when it cannot be decoded.
cv::Mat ColorAlignedDepthM(const ExportScene& scene, const ExportFrame& frame);

}  // namespace mocap::exporters
