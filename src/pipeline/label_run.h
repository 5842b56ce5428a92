#pragma once
// A label run (docs/labels.md): the folder `mocaplabel label` writes. Its layout, its labels.jsonl record
// and its one writer and one reader are here; nothing else in the tree knows them.
//
//   L/run.json                          provenance (provenance.h)
//   L/label_manifest.json               the labeller's summary; its presence marks a finished run
//   L/labels.jsonl                      one LabelRecord per camera frame and object instance
//   L/<camera>/instance/NNNNNN.png      uint16 instance ids        L/<camera>/class/NNNNNN.png  object ids
//   L/<camera>/depth/NNNNNN.exr         rendered depth (metres)    L/<camera>/mask_bits/NNNNNN.png packed masks
//   L/<camera>/{mask,mask_visib,mask_visib_depth}/NNNNNN_IIIIII.png   BOP-style masks (--bop-masks)
//   L/<camera>/overlay/NNNNNN.png       label colours over the RGB image (--overlay)
#include <array>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "label/labeller.h"
#include "session/reader.h"

namespace mocap::pipeline {

/// One line of labels.jsonl (field meanings in docs/labels.md).
struct LabelRecord {
  std::string camera;
  int64_t frame = 0, index = 0, stamp_ns = 0;
  std::string source_id;  ///< "" when the recording has none
  int object = 0;
  std::string name, object_class;
  int instance = 0;
  std::string body;
  std::vector<std::string> flags;
  std::string reason;  ///< without a pose: why
  /// With a pose (rvec present): T_camera_mesh and the labels.
  bool has_pose = false;
  Eigen::Vector3d rvec = Eigen::Vector3d::Zero(), t_m = Eigen::Vector3d::Zero();
  Eigen::Vector4d quat_wxyz = Eigen::Vector4d(1, 0, 0, 0);
  double interp_gap_ms = 0;
  std::optional<double> speed_m_s, speed_deg_s;
  std::array<int, 4> bbox_obj{}, bbox_visib{};
  int64_t px_count_all = 0, px_count_visib = 0;
  std::optional<int64_t> px_count_valid;  ///< with measured depth only
  /// With measured depth only: visible pixels the depth confirms, visible pixels without depth (by the
  /// hole rule or the model), and their share (label/object_labels.h ObjectStats). Absent in label runs
  /// written before these fields.
  std::optional<int64_t> px_count_visib_measured, px_count_visib_assumed;
  std::optional<double> mask_confidence;
  double visib_fract = 0, visib_fract_model = 0;
  std::string visib_source;                ///< "measured_depth" or "model"
  bool has_mask_fields = false;            ///< masks written: mask_rect/mask_row present (null when empty)
  std::optional<std::array<int, 4>> mask_rect;
  std::optional<int> mask_row;
  Rigid3d T_camera_mesh() const { return Rigid3d::FromRvec(rvec, t_m); }
};

nlohmann::json ToJson(const LabelRecord& record);
/// Strict: a missing or mistyped field is an InputError naming `where` (file:line) and the field.
LabelRecord LabelRecordFromJson(const nlohmann::json& json, const std::string& where);
/// The record of one instance of a labelled frame.
LabelRecord MakeLabelRecord(const LabelledFrame& frame, const InstanceResult& result);

/// Paths inside a label run.
struct LabelRunLayout {
  std::filesystem::path dir;
  std::filesystem::path labels_jsonl() const { return dir / "labels.jsonl"; }
  std::filesystem::path manifest_json() const { return dir / "label_manifest.json"; }
  std::filesystem::path FramePng(const std::string& camera, const std::string& kind, int64_t index) const;
  std::filesystem::path InstancePng(const std::string& camera, int64_t index) const { return FramePng(camera, "instance", index); }
  std::filesystem::path ClassPng(const std::string& camera, int64_t index) const { return FramePng(camera, "class", index); }
  std::filesystem::path MaskBitsPng(const std::string& camera, int64_t index) const { return FramePng(camera, "mask_bits", index); }
  std::filesystem::path OverlayPng(const std::string& camera, int64_t index) const { return FramePng(camera, "overlay", index); }
  std::filesystem::path DepthExr(const std::string& camera, int64_t index) const;
  /// kind: mask, mask_visib or mask_visib_depth.
  std::filesystem::path BopMaskPng(const std::string& camera, const std::string& kind, int64_t index, int instance) const;
  /// The per-frame folders a run with `output` has under each camera.
  static std::vector<std::string> FrameFolders(const FrameOutputOptions& output);
};

/// Writes labelled frames as a label run under `dir` (normally an output's .partial folder): the
/// images as they come, labels.jsonl (in camera, then frame order) at Finish().
class LabelRunWriter : public LabelSink {
 public:
  explicit LabelRunWriter(std::filesystem::path dir) : layout_{std::move(dir)} {}
  void Begin(const std::vector<std::string>& cameras, const FrameOutputOptions& output) override;
  void Write(const LabelledFrame& frame) override;
  /// labels.jsonl and label_manifest.json (`manifest`). Throws InputError when a write fails.
  void Finish(const nlohmann::json& manifest);

 private:
  LabelRunLayout layout_;
  FrameOutputOptions output_;
  std::vector<std::string> cameras_;
  std::mutex mutex_;
  std::map<std::pair<size_t, int64_t>, std::string> lines_;  ///< (camera order, index) -> the frame's lines
};

/// A finished label run read back: its records, manifest and layout.
struct LabelRun {
  LabelRunLayout layout;
  nlohmann::json manifest;
  std::vector<LabelRecord> records;
  /// Throws InputError naming the file (and line) for a folder that is not a finished label run or a
  /// malformed record.
  static LabelRun Read(const std::filesystem::path& dir);
};

}  // namespace mocap::pipeline
