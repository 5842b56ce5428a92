#include "pipeline/scoring.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <nlohmann/json.hpp>

#include "core/check.h"
#include "core/rigid3.h"
#include "session/depth_in_color.h"
#include "session/image_io.h"
#include "session/manifest.h"
#include "session/reader.h"
#include "pipeline/json_read.h"
#include "pipeline/label_run.h"
#include "pipeline/visible_masks.h"
#include "sim/record/truth_io.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

struct TrueObject {
  int id = 0;
  Rigid3d T_camera_mesh;  ///< colour optical frame at the colour exposure: what a label describes
};
using TruthPoses = std::map<int64_t, std::map<std::string, TrueObject>>;  // frame index -> object name

TruthPoses ReadTruthPoses(const fs::path& truth_dir) {
  TruthPoses poses;
  const fs::path file = truth_dir / "poses.jsonl";
  for (const auto& [where, frame] : ReadJsonLines(file))
    for (const nlohmann::json& o : frame.at("objects"))
      poses[frame.at("index").get<int64_t>()][o.at("name").get<std::string>()] =
          TrueObject{o.at("id").get<int>(), RigidFromJson(o.at("T_color_mesh"), file.string())};
  return poses;
}

/// IoU of the label mask (`in_label(u, v)`, over `size`'s pixels) and (truth == true_value); -1 when both
/// are empty.
template <typename InLabel>
double MaskIou(const LabelImage& size, InLabel in_label, const LabelImage& truth, int true_value, RecordScore& score) {
  int64_t inter = 0, uni = 0;
  score.true_pixels = score.label_pixels = 0;
  for (int v = 0; v < size.height; ++v) {
    for (int u = 0; u < size.width; ++u) {
      const bool a = in_label(u, v), b = truth.at(u, v) == true_value;
      inter += a && b, uni += a || b;
      score.label_pixels += a, score.true_pixels += b;
    }
  }
  return uni > 0 ? double(inter) / double(uni) : -1.0;
}


/// The label's visible masks of a frame, from the measured depth as the labeller reads it: in the colour
/// image (a Kinect v2's registered there), with the colour image for the colour test on holes.
std::map<uint16_t, Image<uint8_t>> LabelVisibleMasks(const SessionReader& session, VisibleMaskRenderer& masks,
                                                     const std::string& camera, int64_t index,
                                                     const std::vector<LabelledPose>& poses) {
  const CameraStreamInfo* info = session.manifest().FindCamera(camera);
  if (!info) throw InputError(session.dir().string(), Str("labels name camera '", camera, "', not in the session"));
  const DepthImage depth = LoadDepthInColor(session, camera, index, DepthInColor::Of(*info, masks.camera()));
  const VisibilityOptions& visibility = masks.visibility();
  if (!visibility.hole_colour || visibility.rule != VisibilityRule::kCombined || !session.frame(camera, index).color_present)
    return masks.Masks(poses, depth);
  const cv::Mat color = session.LoadColor(camera, index);
  const BgrView bgr{color.cols, color.rows, color.data, color.step[0]};
  return masks.Masks(poses, depth, &bgr);
}

/// Scores the records of one frame into `scores`.
void ScoreFrame(const std::vector<const LabelRecord*>& records, const TruthPoses& truth, const LabelRunLayout& labels,
                const fs::path& truth_dir, const SessionReader* session, VisibleMaskRenderer* masks, LabelScores& scores) {
  // `index` is the record's place in the labelled session, `frame` the simulated frame it shows (they
  // differ once a recording dropped frames); the truth is kept by simulated frame.
  const int64_t index = records[0]->index;
  const int64_t frame = records[0]->frame;
  const std::string& camera = records[0]->camera;
  ++scores.frames;
  const auto frame_truth = truth.find(frame);
  std::vector<LabelledPose> poses;
  std::vector<RecordScore> scored;
  for (const LabelRecord* r : records) {
    if (!r->has_pose) {
      ++scores.records_without_pose;
      continue;
    }
    ++scores.records_with_pose;
    if (frame_truth == truth.end() || !frame_truth->second.count(r->name))
      throw InputError(labels.labels_jsonl().string(), Str("record of '", r->name, "' in frame ", frame, " has no truth in ", truth_dir.string()));
    const TrueObject& t = frame_truth->second.at(r->name);
    const Rigid3d label = r->T_camera_mesh();
    poses.push_back({r->name, static_cast<uint16_t>(r->instance), label});
    scored.push_back({frame, r->name, 1000.0 * (label.translation() - t.T_camera_mesh.translation()).norm(),
                      RotationDistanceDeg(label, t.T_camera_mesh)});
  }
  if (scored.empty()) return;
  const LabelImage label_ids = ReadIdImage(labels.InstancePng(camera, index));
  const LabelImage true_ids = ReadIdImage(sim::TruthInstancePng(truth_dir, frame));
  if (label_ids.width != true_ids.width || label_ids.height != true_ids.height)
    throw InputError(labels.dir.string(), Str("instance image of frame ", index, " differs in size from the truth's"));
  std::map<uint16_t, Image<uint8_t>> measured;
  if (masks && session) measured = LabelVisibleMasks(*session, *masks, camera, index, poses);
  for (size_t i = 0; i < scored.size(); ++i) {
    RecordScore& s = scored[i];
    const int true_id = frame_truth->second.at(s.object).id;
    s.iou_model = MaskIou(label_ids, [&](int u, int v) { return label_ids.at(u, v) == poses[i].instance; },
                          true_ids, true_id, s);
    s.iou = s.iou_model;
    if (masks && session) {
      const Image<uint8_t>& m = measured.at(poses[i].instance);
      s.iou = MaskIou(label_ids, [&](int u, int v) { return m.at(u, v) != 0; }, true_ids, true_id, s);
    }
    scores.per_record.push_back(s);
  }
}

void Summarise(LabelScores& scores) {
  std::vector<double> ious, ious_model, err_mm, err_deg;
  for (const RecordScore& s : scores.per_record) {
    if (s.iou >= 0) ious.push_back(s.iou);
    if (s.iou_model >= 0) ious_model.push_back(s.iou_model);
    err_mm.push_back(s.err_mm), err_deg.push_back(s.err_deg);
  }
  auto mean = [](const std::vector<double>& x) {
    double sum = 0;
    for (double v : x) sum += v;
    return x.empty() ? 0.0 : sum / double(x.size());
  };
  scores.mask_iou_mean = mean(ious), scores.mask_iou_p5 = Percentile(ious, 5);
  scores.mask_iou_model_mean = mean(ious_model), scores.mask_iou_model_p5 = Percentile(ious_model, 5);
  scores.pose_err_mm_median = Percentile(err_mm, 50), scores.pose_err_mm_p95 = Percentile(err_mm, 95);
  scores.pose_err_deg_median = Percentile(err_deg, 50), scores.pose_err_deg_p95 = Percentile(err_deg, 95);
}

}  // namespace

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const double x = std::clamp(p, 0.0, 100.0) / 100.0 * double(values.size() - 1);
  const auto i = static_cast<size_t>(std::floor(x));
  const size_t j = std::min(i + 1, values.size() - 1);
  return values[i] + (x - double(i)) * (values[j] - values[i]);
}

LabelScores ScoreLabels(const fs::path& labels_dir, const fs::path& truth_dir, const SessionReader* session,
                        VisibleMaskRenderer* masks) {
  const TruthPoses truth = ReadTruthPoses(truth_dir);
  const LabelRun run = LabelRun::Read(labels_dir);
  LabelScores scores;
  std::vector<const LabelRecord*> frame;  // records of one (camera, index), as labels.jsonl lists them
  auto flush = [&] {
    if (!frame.empty()) ScoreFrame(frame, truth, run.layout, truth_dir, session, masks, scores);
    frame.clear();
  };
  for (const LabelRecord& r : run.records) {
    ++scores.records;
    if (!frame.empty() && (r.index != frame[0]->index || r.camera != frame[0]->camera)) flush();
    frame.push_back(&r);
  }
  flush();
  Summarise(scores);
  return scores;
}

}  // namespace mocap::pipeline
