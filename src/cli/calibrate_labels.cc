#include "cli/calibrate_labels.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "cli/calibrate_views.h"
#include "core/check.h"
#include "pipeline/calibration_records.h"
#include "pipeline/label_run.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/provenance.h"
#include "pipeline/rig.h"
#include "pipeline/validation_run.h"
#include "session/reader.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path LabelsDir(const LabelsCalibrationArgs& a) { return a.labels.empty() ? fs::path(a.session) / "labels" : fs::path(a.labels); }

/// The file the label run recorded for `role` ("rig", "objects"), when it recorded one that still exists.
fs::path RecordedInput(const fs::path& labels_dir, const std::string& role) {
  for (const pipeline::InputRecord& input : pipeline::ReadRunJson(labels_dir).inputs)
    if (input.role == role && fs::is_regular_file(input.path)) return input.path;
  return {};
}

pipeline::ObjectLibrary Library(const LabelsCalibrationArgs& a) {
  const fs::path recorded = a.objects.empty() ? RecordedInput(LabelsDir(a), "objects") : fs::path();
  return pipeline::ReadObjectLibrary(!a.objects.empty() ? fs::path(a.objects)
                                     : !recorded.empty() ? recorded
                                                         : pipeline::FindObjectsFile(a.session, ""));
}

std::string RigFile(const LabelsCalibrationArgs& a) {
  return a.rig.empty() ? RecordedInput(LabelsDir(a), "rig").string() : a.rig;
}

/// The object's records with a reliable SegICP estimate: from --validation, or checked here.
std::vector<RecordCheck> ObjectRecords(const LabelsCalibrationArgs& a, const pipeline::ObjectLibrary& library, int object_id) {
  std::vector<RecordCheck> all;
  if (!a.validation.empty()) {
    all = pipeline::ValidationRun::Read(a.validation).records;
  } else {
    const SessionReader session = SessionReader::Open(a.session);
    const pipeline::LabelRun labels = pipeline::LabelRun::Read(LabelsDir(a));
    SessionCheckOptions options;
    options.labels_dir = LabelsDir(a);
    options.frame_stride = a.frame_stride;
    for (const pipeline::LibraryObject& o : library.objects)
      if (o.id != object_id) options.skip_objects.push_back(o.id);
    all = CheckSession(session, pipeline::ValidationObjectsOf(library), pipeline::LabelRunViewOf(labels), options).records;
  }
  std::vector<RecordCheck> kept;
  for (RecordCheck& r : all)
    if (r.object == object_id && r.check.estimated && r.check.segicp_reliable) kept.push_back(std::move(r));
  return kept;
}

}  // namespace

int CalibrateObjectMountFromLabels(const LabelsCalibrationArgs& a, const ObjectMountOptions& options) {
  options.check();
  RefuseExisting(a.out, a.force);
  pipeline::ObjectLibrary library = Library(a);
  const pipeline::LibraryObject& object = ObjectOnOneBody(library, a.object);
  const BodyMount mount = object.mounts.front();
  std::vector<LabelEstimatePair> pairs;
  for (const RecordCheck& r : ObjectRecords(a, library, object.id)) pairs.push_back({r.T_camera_object_label, r.check.T_camera_object_segicp});
  const ObjectMountResult r = EstimateObjectMount(pairs, mount.T_body_mesh, options);
  const Eigen::Vector3d dt_mm = 1e3 * r.correction.translation();
  if (a.json) {
    std::printf("%s\n", json{{"object", a.object}, {"body", mount.body}, {"T_body_mesh", PoseJson(r.T_objbody_mesh)},
                             {"T_body_mesh_before", PoseJson(mount.T_body_mesh)},
                             {"change_mm", dt_mm.norm()}, {"change_deg", DegFromRad(r.correction.rvec().norm())},
                             {"records_used", r.records_used}, {"records_dropped", r.records_dropped},
                             {"spread_mm", r.spread_mm}, {"spread_deg", r.spread_deg}, {"ci95_mm", r.ci95_mm},
                             {"ci95_deg", r.ci95_deg}, {"autocorrelation", r.autocorrelation}, {"warnings", r.warnings}}
                            .dump().c_str());
  } else {
    std::printf("mount of %s on %s from %d records (%d dropped): changes by %.2f mm, %.3f deg\n", a.object.c_str(),
                mount.body.c_str(), r.records_used, r.records_dropped, dt_mm.norm(), DegFromRad(r.correction.rvec().norm()));
    std::printf("spread %.2f mm / %.3f deg per record; 95 %% interval of the estimate +-%.2f mm / +-%.3f deg\n",
                r.spread_mm, r.spread_deg, r.ci95_mm, r.ci95_deg);
    for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
  }
  if (a.out.empty()) return 0;
  for (pipeline::LibraryObject& o : library.objects)
    if (o.name == a.object) o.mounts.front().T_body_mesh = r.T_objbody_mesh;
  WriteLibrary(library, a.out,
               Str("mount of ", a.object, " on ", mount.body, " from the depth of ", a.session, " (", r.records_used,
                                   " records, +-", r.ci95_mm, " mm / +-", r.ci95_deg, " deg) by mocaplabel calibrate object-mount"));
  return 0;
}

}  // namespace mocap::cli

namespace mocap::cli {
namespace {

/// What the calibration would be with the findings applied: the rig (camera mounts, latency) and the
/// object library (object mounts); `changed_*` say whether a file needs writing.
struct Corrected {
  pipeline::Rig rig;
  pipeline::ObjectLibrary library;
  bool changed_rig = false, changed_library = false;
  json findings = json::array();
};

json FindingJson(const CheckFinding& f) {
  json j = {{"item", ToString(f.kind)}, {"name", f.name}, {"explained_share", f.explained_share}, {"alike", f.alike}};
  if (f.kind == CheckItemKind::kLatency) {
    j["latency_error_ms"] = f.latency_error_ms, j["latency_ci95_ms"] = f.latency_ci95_ms;
  } else {
    j["size_mm"] = f.size_mm, j["ci95_mm"] = f.ci95_mm, j["size_deg"] = f.size_deg, j["ci95_deg"] = f.ci95_deg;
    j["correction"] = PoseJson(f.correction);
  }
  return j;
}

Corrected ApplyFindings(const LabelsCalibrationArgs& a, const CalibrationCheckResult& result, const std::string& first_camera) {
  Corrected c{OpenCalibrationInputs(a.session, RigFile(a), first_camera).rig, Library(a)};
  for (const CheckFinding& f : result.findings) {
    json j = FindingJson(f);
    if (f.kind == CheckItemKind::kLatency) {
      c.rig.tracker_latency_ns -= std::llround(f.latency_error_ms * 1e6);
      j["corrected_tracker_latency_ms"] = static_cast<double>(c.rig.tracker_latency_ns) / 1e6;
      c.changed_rig = true;
    } else if (f.kind == CheckItemKind::kCameraMount) {
      const CalibrationInputs in = OpenCalibrationInputs(a.session, RigFile(a), f.name);
      const pipeline::RigCameraCalibration* cal = in.rig.Find(f.name);
      if (!cal || !cal->T_body_camera) throw InputError(RigFile(a), "camera '" + f.name + "' has no mount to correct");
      const Rigid3d corrected = *cal->T_body_camera * f.correction.inverse();
      SetMount(c.rig, f.name, in.camera_body, corrected);
      j["corrected_T_body_camera"] = PoseJson(corrected);
      c.changed_rig = true;
    } else {
      for (pipeline::LibraryObject& o : c.library.objects)
        if (o.name == f.name && o.mounts.size() == 1) {
          o.mounts.front().T_body_mesh = o.mounts.front().T_body_mesh * f.correction;
          j["corrected_T_body_mesh"] = PoseJson(o.mounts.front().T_body_mesh);
          c.changed_library = true;
        }
    }
    c.findings.push_back(j);
  }
  return c;
}

void PrintCheck(const CalibrationCheckResult& r, const Corrected& c) {
  std::printf("calibration check from %d reliable SegICP estimates (%d with motion):\n", r.records, r.records_with_motion);
  if (r.findings.empty()) std::printf("  nothing looks wrong\n");
  for (const CheckFinding& f : r.findings) {
    if (f.kind == CheckItemKind::kLatency)
      std::printf("  the tracker latency looks off by %+.1f ms (95 %%: +-%.1f ms): set it to %.1f ms\n", f.latency_error_ms,
                  f.latency_ci95_ms, static_cast<double>(c.rig.tracker_latency_ns) / 1e6);
    else
      std::printf("  the %s of %s looks off by %s; explains %.0f %% of the disagreement\n",
                  f.kind == CheckItemKind::kCameraMount ? "camera mount" : "object mount", f.name.c_str(), MountSizeText(f).c_str(),
                  100 * f.explained_share);
  }
  std::printf("  median disagreement per camera/object, mm / deg, before -> after the corrections:\n");
  for (const ResidualSummary& s : r.residuals)
    std::printf("    %s/%s (%d): %.2f / %.3f -> %.2f / %.3f\n", s.camera.c_str(), s.object.c_str(), s.records,
                s.median_mm_before, s.median_deg_before, s.median_mm_after, s.median_deg_after);
  for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
}

}  // namespace

int CheckCalibrationOfLabels(const LabelsCalibrationArgs& a, const CalibrationCheckOptions& options) {
  options.check();
  RefuseExisting(a.write_rig, a.force);
  RefuseExisting(a.write_objects, a.force);
  const pipeline::ValidationRun run = pipeline::ValidationRun::Read(a.validation);
  const std::vector<CheckRecord> records = pipeline::CalibrationCheckRecords(run.records, pipeline::ValidationObjectsOf(Library(a)));
  const CalibrationCheckResult result = CheckCalibration(records, options);
  const Corrected c = ApplyFindings(a, result, records.front().camera);
  if (a.json) {
    json residuals = json::array();
    for (const ResidualSummary& s : result.residuals)
      residuals.push_back({{"camera", s.camera}, {"object", s.object}, {"records", s.records},
                           {"median_mm_before", s.median_mm_before}, {"median_deg_before", s.median_deg_before},
                           {"median_mm_after", s.median_mm_after}, {"median_deg_after", s.median_deg_after}});
    std::printf("%s\n", json{{"records", result.records}, {"records_with_motion", result.records_with_motion}, {"objects_left_out", result.objects_left_out},
                             {"findings", c.findings}, {"residuals", residuals}, {"autocorrelation", result.autocorrelation},
                             {"warnings", result.warnings}}.dump().c_str());
  } else {
    PrintCheck(result, c);
  }
  const std::string why = Str("corrected by mocaplabel calibrate check of ", a.session, " (", a.validation, ")");
  if (!a.write_rig.empty() && c.changed_rig) {
    pipeline::WriteRig(c.rig, a.write_rig, Provenance(why));
    std::fprintf(stderr, "wrote %s\n", a.write_rig.c_str());
  }
  if (!a.write_objects.empty() && c.changed_library) WriteLibrary(c.library, a.write_objects, why);
  if ((!a.write_rig.empty() && !c.changed_rig) || (!a.write_objects.empty() && !c.changed_library))
    std::fprintf(stderr, "nothing to correct in %s\n", (!c.changed_rig && !a.write_rig.empty() ? a.write_rig : a.write_objects).c_str());
  return 0;
}

}  // namespace mocap::cli
