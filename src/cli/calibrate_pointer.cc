#include "cli/calibrate_pointer.h"

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "cli/calibrate_views.h"
#include "cli/pointer_yaml.h"
#include "core/check.h"
#include "core/pose_stream.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "session/reader.h"

namespace mocap::cli {
namespace {

using nlohmann::json;

/// The valid samples of `body`; InputError naming the body when no tracker of the session reports it.
std::vector<PoseSample> BodySamples(const SessionReader& session, const std::string& body, const std::string& what) {
  const std::optional<std::string> tracker = session.TrackerOfBody(body);
  if (!tracker) throw InputError(session.dir().string(), "no tracker of the session reports body '" + body + "' (" + what + ")");
  std::vector<PoseSample> valid;
  for (const PoseSample& s : session.PoseSamples(*tracker, body))
    if (HasPose(s.status)) valid.push_back(s);
  if (valid.empty()) throw InputError(session.dir().string(), "body '" + body + "' (" + what + ") was never tracked");
  return valid;
}

json Vector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

int CalibratePivotOfSession(const PointerArgs& a, const PivotOptions& options) {
  options.check();
  if (a.from_s < 0 || a.to_s < 0 || (a.to_s > 0 && a.to_s <= a.from_s))
    throw InputError("--from-s/--to-s", "need 0 <= from < to (seconds after the pointer's first sample; to 0 = the end)");
  RefuseExisting(a.out, a.force);
  const SessionReader session = SessionReader::Open(a.session);
  const std::vector<PoseSample> samples = BodySamples(session, a.pointer_body, "the pointer");
  std::vector<Rigid3d> poses;
  for (const PoseSample& s : samples) {
    const double t_s = static_cast<double>(s.stamp_ns - samples.front().stamp_ns) * 1e-9;
    if (t_s >= a.from_s && (a.to_s == 0 || t_s <= a.to_s)) poses.push_back(s.pose);
  }
  const PivotResult r = CalibratePivot(poses, options);
  if (a.json) {
    std::printf("%s\n", json{{"pointer_body", a.pointer_body}, {"tip_m", Vector(r.p_pointer_tip)}, {"pivot_tracker_m", Vector(r.p_tracker_pivot)},
                             {"rms_mm", r.rms_mm}, {"rotation_spread_deg", r.rotation_spread_deg}, {"condition", r.condition},
                             {"samples_used", r.samples_used}, {"samples_dropped", r.samples_dropped}, {"warnings", r.warnings}}
                            .dump().c_str());
  } else {
    std::printf("tip of %s at [%.2f, %.2f, %.2f] mm in its body frame from %d poses (%d dropped), turning %.1f deg\n",
                a.pointer_body.c_str(), 1e3 * r.p_pointer_tip.x(), 1e3 * r.p_pointer_tip.y(), 1e3 * r.p_pointer_tip.z(),
                r.samples_used, r.samples_dropped, r.rotation_spread_deg);
    std::printf("tip wobble about the divot: %.3f mm RMS\n", r.rms_mm);
    for (const std::string& w : r.warnings) std::printf("warning: %s\n", w.c_str());
  }
  if (a.out.empty()) return 0;
  WritePointerFile({a.pointer_body, r.p_pointer_tip}, a.out,
                   Provenance(Str("pointer tip by pivot calibration of ", a.session, " (", r.samples_used, " poses, ", r.rms_mm,
                       " mm RMS) by mocaplabel calibrate pivot")));
  std::fprintf(stderr, "wrote %s\n", a.out.c_str());
  return 0;
}

}  // namespace mocap::cli

namespace mocap::cli {
namespace {

/// The pointer's tip in the object body's frame at every pointer sample where the object is tracked too.
void TipInObjectBody(const SessionReader& session, const PointerTool& pointer, const std::string& object_body,
                     std::vector<int64_t>& stamps_ns, std::vector<Eigen::Vector3d>& p_objbody) {
  if (session.TrackerOfBody(pointer.body) != session.TrackerOfBody(object_body))
    throw InputError(session.dir().string(), "the pointer '" + pointer.body + "' and the object's body '" + object_body +
                                                 "' must be reported by the same tracker");
  const std::vector<PoseSample> object = BodySamples(session, object_body, "the object");
  for (const PoseSample& s : BodySamples(session, pointer.body, "the pointer")) {
    const InterpolatedPose T_tracker_objbody = InterpolatePose(object, s.stamp_ns);
    if (!T_tracker_objbody.ok()) continue;
    stamps_ns.push_back(s.stamp_ns);
    p_objbody.push_back(T_tracker_objbody.pose->inverse() * (s.pose * pointer.tip_m));
  }
}

std::string TouchTimes(const std::vector<Touch>& touches, int64_t start_ns) {
  std::string out;
  for (const Touch& t : touches)
    out += Str(out.empty() ? "" : ", ", static_cast<double>(t.start_ns - start_ns) * 1e-9, "-", static_cast<double>(t.end_ns - start_ns) * 1e-9, " s");
  return out;
}

}  // namespace

namespace {

/// The pointer's rests in the session and which of them were the landmarks (InputError saying what to
/// record when they cannot be matched).
struct LandmarkTouches {
  std::vector<Touch> rests, touches;  ///< touches: one rest per landmark, in the landmarks' order
  TouchMatch match;
};

LandmarkTouches FindLandmarkTouches(const PointerArgs& a, const SessionReader& session, const PointerTool& pointer,
                                    const std::string& object_body, const Landmarks& landmarks, const TouchOptions& options) {
  std::vector<int64_t> stamps_ns;
  std::vector<Eigen::Vector3d> p_objbody;
  TipInObjectBody(session, pointer, object_body, stamps_ns, p_objbody);
  LandmarkTouches t;
  t.rests = FindTouches(stamps_ns, p_objbody, options);
  const int64_t start_ns = stamps_ns.empty() ? 0 : stamps_ns.front();
  try {
    t.match = MatchTouchesToLandmarks(t.rests, landmarks.p_mesh_m);
  } catch (const InputError& e) {
    throw InputError(a.session, Str(e.what(), " (rests at ", TouchTimes(t.rests, start_ns), "; ", a.landmarks, " lists ",
                                    landmarks.names.size(), "; a touch is the tip held still for ", options.min_still_s, " s)"));
  }
  if (t.match.distance_rms_mm > options.max_mismatch_mm)
    throw InputError(a.session, Str("no choice of the pointer's ", t.rests.size(), " rests (", TouchTimes(t.rests, start_ns),
                                    ") is as far apart as the landmarks of ", a.landmarks, " (best: ", t.match.distance_rms_mm,
                                    " mm RMS off): touch them in the file's order, and check the landmarks' unit"));
  for (int i : t.match.touches) t.touches.push_back(t.rests[static_cast<size_t>(i)]);
  return t;
}

void PrintPointerMount(const PointerArgs& a, const std::string& body, const Landmarks& landmarks, const LandmarkTouches& t,
                       const PairedPointResult& r, const Rigid3d& change) {
  const double change_mm = 1e3 * change.translation().norm(), change_deg = DegFromRad(change.rvec().norm());
  if (a.json) {
    json per = json::array();
    for (size_t i = 0; i < t.touches.size(); ++i)
      per.push_back({{"name", landmarks.names[i]}, {"fre_mm", r.fre_mm[i]}, {"rest_spread_mm", t.touches[i].spread_mm},
                     {"samples", t.touches[i].samples}});
    std::printf("%s\n", json{{"object", a.object}, {"body", body}, {"T_body_mesh", PoseJson(r.T_objbody_mesh)}, {"fre_rms_mm", r.fre_rms_mm},
                             {"landmarks", per}, {"rests", t.rests.size()}, {"distance_rms_mm", t.match.distance_rms_mm},
                             {"change_mm", change_mm}, {"change_deg", change_deg}}
                            .dump()
                            .c_str());
    return;
  }
  std::printf("mount of %s on %s from %zu touched landmarks: registration error %.2f mm RMS; changes by %.2f mm, %.3f deg\n",
              a.object.c_str(), body.c_str(), t.touches.size(), r.fre_rms_mm, change_mm, change_deg);
  if (t.rests.size() > t.touches.size())
    std::printf("  %zu other rests of the pointer were not at landmarks (distances off by %.2f mm RMS for the ones used)\n",
                t.rests.size() - t.touches.size(), t.match.distance_rms_mm);
  for (size_t i = 0; i < t.touches.size(); ++i)
    std::printf("  %s: %.2f mm (tip still within %.2f mm over %d samples)\n", landmarks.names[i].c_str(), r.fre_mm[i],
                t.touches[i].spread_mm, t.touches[i].samples);
}

}  // namespace

int CalibrateObjectMountFromPointer(const PointerArgs& a, const TouchOptions& options) {
  options.check();
  RefuseExisting(a.out, a.force);
  const PointerTool pointer = ReadPointerFile(a.pointer);
  const Landmarks landmarks = ReadLandmarksFile(a.landmarks);
  pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(pipeline::FindObjectsFile(a.session, a.objects));
  const BodyMount mount = ObjectOnOneBody(library, a.object).mounts.front();
  const LandmarkTouches t = FindLandmarkTouches(a, SessionReader::Open(a.session), pointer, mount.body, landmarks, options);
  std::vector<Eigen::Vector3d> touched;
  for (const Touch& touch : t.touches) touched.push_back(touch.p_objbody);
  const PairedPointResult r = RegisterPairedPoints(touched, landmarks.p_mesh_m);
  PrintPointerMount(a, mount.body, landmarks, t, r, mount.T_body_mesh.inverse() * r.T_objbody_mesh);
  if (a.out.empty()) return 0;
  for (pipeline::LibraryObject& o : library.objects)
    if (o.name == a.object) o.mounts.front().T_body_mesh = r.T_objbody_mesh;
  WriteLibrary(library, a.out, Str("mount of ", a.object, " on ", mount.body, " from ", t.touches.size(), " landmarks touched in ", a.session,
                                   " (", r.fre_rms_mm, " mm RMS) by mocaplabel calibrate object-mount --pointer"));
  return 0;
}

}  // namespace mocap::cli
