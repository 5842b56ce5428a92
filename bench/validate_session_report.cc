#include "validate_session_report.h"

#include <algorithm>
#include <cstdio>
#include <tuple>

#include "core/check.h"
#include "pipeline/json_read.h"
#include "pipeline/scoring.h"
#include "session/manifest.h"

namespace mocap::bench {
namespace {

namespace fs = std::filesystem;

/// The true T_camera_mesh per (simulated frame, object name).
using Truth = std::map<std::pair<int64_t, std::string>, Rigid3d>;
Truth ReadTruth(const fs::path& truth_dir) {
  Truth truth;
  const fs::path file = truth_dir / "poses.jsonl";
  for (const auto& [where, frame] : pipeline::ReadJsonLines(file))
    for (const nlohmann::json& o : frame.at("objects"))
      truth[{frame.at("index").get<int64_t>(), o.at("name").get<std::string>()}] = RigidFromJson(o.at("T_color_mesh"), where);
  return truth;
}

/// Errors collected per group before their spread is taken.
struct Errors {
  Accuracy accuracy;
  std::vector<double> position_mm, rotation_deg;
  void Add(const LabelCheck& check, const Rigid3d& truth) {
    ++accuracy.checked;
    accuracy.accepted += check.verdict == Verdict::kAccept;
    accuracy.success += check.success;
    if (!check.estimated) return;
    position_mm.push_back(1e3 * TranslationDistanceM(check.T_camera_object_segicp, truth));
    rotation_deg.push_back(RotationDistanceDeg(check.T_camera_object_segicp, truth));
  }
  Accuracy Done() const {
    Accuracy a = accuracy;
    a.position_mm = {pipeline::Percentile(position_mm, 50), pipeline::Percentile(position_mm, 95)};
    a.rotation_deg = {pipeline::Percentile(rotation_deg, 50), pipeline::Percentile(rotation_deg, 95)};
    return a;
  }
};

double Percent(int64_t part, int64_t whole) { return 100.0 * static_cast<double>(part) / static_cast<double>(std::max<int64_t>(1, whole)); }

}  // namespace

void ScoreRun(const SessionValidation& validation, const pipeline::LabelRun& labels, const fs::path& truth_dir,
              BackendRun* run) {
  std::map<std::tuple<std::string, int64_t, int>, int64_t> frame_of;  // (camera, index, instance) -> simulated frame
  for (const pipeline::LabelRecord& r : labels.records) frame_of[{r.camera, r.index, r.instance}] = r.frame;
  const Truth truth = truth_dir.empty() ? Truth() : ReadTruth(truth_dir);
  Errors all;
  std::map<std::string, Errors> per_object;
  for (const RecordCheck& r : validation.records) {
    if (IsBadInput(r.check.reason_code)) continue;
    Rigid3d reference = r.T_camera_object_label;
    if (!truth_dir.empty()) {
      const auto it = truth.find({frame_of.at({r.camera, r.index, r.instance}), r.name});
      if (it == truth.end()) throw InputError(truth_dir.string(), Str("has no pose of ", r.name, " at frame ", r.index));
      reference = it->second;
    }
    all.Add(r.check, reference);
    per_object[r.name].Add(r.check, reference);
  }
  run->records = static_cast<int64_t>(validation.records.size());
  run->all = all.Done();
  for (const auto& [name, errors] : per_object) run->per_object[name] = errors.Done();
}

void PrintCase(const std::string& name, const ReplayedSteps& steps, const std::vector<BackendRun>& runs) {
  std::printf("\n%s\n| backend | records | records/s | wall s | CPU s | registration (p2p + p2plane s) | frames read | scene clouds "
              "| rest | accepted | SegICP success | position mm median / p95 | rotation deg median / p95 |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n", name.c_str());
  for (const BackendRun& r : runs) {
    const double registration_s = r.point_to_point_s + r.point_to_plane_s;
    const auto share = [&](double s) { return 100.0 * s / r.cpu_s; };
    const Accuracy& a = r.all;
    std::printf("| %s | %lld | %.1f | %.1f | %.1f | %.0f %% (%.1f + %.1f) | %.0f %% | %.0f %% | %.0f %% | %.1f %% | %.1f %% "
                "| %.2f / %.2f | %.3f / %.3f |\n",
                r.backend.c_str(), static_cast<long long>(r.records), static_cast<double>(r.records) / r.wall_s, r.wall_s,
                r.cpu_s, share(registration_s), r.point_to_point_s, r.point_to_plane_s, share(steps.io_s),
                share(steps.scene_cloud_s), share(r.cpu_s - registration_s - steps.io_s - steps.scene_cloud_s),
                Percent(a.accepted, a.checked), Percent(a.success, a.checked), a.position_mm.median, a.position_mm.p95,
                a.rotation_deg.median, a.rotation_deg.p95);
  }
  for (size_t i = 1; i < runs.size(); ++i)
    std::printf("%s / %s: wall %.2fx, CPU %.2fx, registration CPU %.2fx\n", runs[i].backend.c_str(), runs[0].backend.c_str(),
                runs[i].wall_s / runs[0].wall_s, runs[i].cpu_s / runs[0].cpu_s,
                (runs[i].point_to_point_s + runs[i].point_to_plane_s) / (runs[0].point_to_point_s + runs[0].point_to_plane_s));
  std::printf("\n| object | backend | checked | accepted | SegICP success | position mm median / p95 | rotation deg median / p95 |\n"
              "|---|---|---|---|---|---|---|\n");
  for (const auto& [object, unused] : runs.front().per_object)
    for (const BackendRun& r : runs) {
      const Accuracy& a = r.per_object.at(object);
      std::printf("| %s | %s | %lld | %.1f %% | %.1f %% | %.2f / %.2f | %.3f / %.3f |\n", object.c_str(), r.backend.c_str(),
                  static_cast<long long>(a.checked), Percent(a.accepted, a.checked), Percent(a.success, a.checked),
                  a.position_mm.median, a.position_mm.p95, a.rotation_deg.median, a.rotation_deg.p95);
    }
}

}  // namespace mocap::bench
