#pragma once
// Scores a label run of a simulated session against its truth (S/truth/), from the files alone, so any
// `mocaplabel sim record` + `mocaplabel label` run can be scored the same way (docs/simulation.md
// "Scores"):
//  - pose error: each labels.jsonl record with a pose (rvec, t_m: T_camera_mesh as labelled) against the
//    true T_camera_mesh of the same frame and object (truth/poses.jsonl): translation error of the mesh
//    origin (mm) and rotation angle of R_label R_true^T (deg);
//  - mask IoU: the label's visible mask against the true visible mask (truth/instance/<frame>.png == the
//    object's id; the truth includes the occluders, so a hand in front of an object counts against the
//    label), for records with a pose whose masks are not both empty. The label's visible mask is BOP's
//    mask_visib against the measured depth (visible_masks.h) when a mask renderer is given, else the
//    z-buffer of the label instance image (labels <camera>/instance/<frame>.png == the record's
//    instance), which knows nothing of occluders; both are reported when the renderer is given.
//    Records without a pose are counted, not scored.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace mocap {
class SessionReader;
}

namespace mocap::pipeline {

class VisibleMaskRenderer;

struct RecordScore {
  int64_t index = 0;  ///< the simulated frame (truth/poses.jsonl index) the record labels
  std::string object;
  double err_mm = 0, err_deg = 0;
  double iou = -1;        ///< -1 when both masks are empty
  double iou_model = -1;  ///< of the instance image's mask
  int true_pixels = 0, label_pixels = 0;
};

struct LabelScores {
  int64_t records = 0;             ///< labels.jsonl records
  int64_t records_with_pose = 0;
  int64_t records_without_pose = 0;
  int64_t frames = 0;              ///< distinct frames in labels.jsonl
  double mask_iou_mean = 0, mask_iou_p5 = 0;
  double mask_iou_model_mean = 0, mask_iou_model_p5 = 0;  ///< instance-image masks (z-buffer of objects only)
  double pose_err_mm_median = 0, pose_err_mm_p95 = 0;
  double pose_err_deg_median = 0, pose_err_deg_p95 = 0;
  std::vector<RecordScore> per_record;
};

/// Percentile p in [0, 100] of `values` (linear interpolation between order statistics); 0 when empty.
double Percentile(std::vector<double> values, double p);

/// Scores `labels_dir` (labels.jsonl, <camera>/instance/) against `truth_dir` (poses.jsonl, instance/).
/// Throws InputError naming the file when one is missing or malformed, or a record names a frame or
/// object the truth does not have.
/// With `session` and `masks` (the session's camera and the label run's objects), the label's visible
/// masks use the measured depth; otherwise the instance images (mask_iou_* = mask_iou_model_*).
LabelScores ScoreLabels(const std::filesystem::path& labels_dir, const std::filesystem::path& truth_dir,
                        const SessionReader* session = nullptr, VisibleMaskRenderer* masks = nullptr);

}  // namespace mocap::pipeline
