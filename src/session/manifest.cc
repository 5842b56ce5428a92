#include "session/manifest.h"

#include <cmath>
#include <fstream>
#include <set>

#include "core/check.h"
#include "session/durable_file.h"
#include "session/json_fields.h"

namespace mocap {
namespace fs = std::filesystem;
using namespace json_fields;

namespace {

/// A name used as a folder: non-empty, no path separators, not "." or "..".
void CheckStreamName(const std::string& name, const std::string& where) {
  if (name.empty() || name == "." || name == ".." || name.find_first_of("/\\") != std::string::npos ||
      name.find('\0') != std::string::npos)
    throw InputError(where, Str("stream name '", name, "' must be a plain, non-empty file name"));
}

std::vector<double> Numbers(const nlohmann::json& object, const char* key, size_t count, const std::string& where) {
  const auto& value = Field(object, key, where);
  if (!value.is_array() || value.size() != count)
    throw InputError(where, Str("field '", key, "' should be an array of ", count, " numbers"));
  std::vector<double> numbers;
  for (const auto& element : value) {
    if (!element.is_number()) throw InputError(where, Str("field '", key, "' should hold numbers only"));
    numbers.push_back(element.get<double>());
  }
  return numbers;
}

nlohmann::json ToJson(const CameraStreamInfo& camera) {
  return {{"name", camera.name},
          {"model", camera.model},
          {"serial", camera.serial},
          {"color_camera", ToJson(camera.color_camera)},
          {"depth_camera", ToJson(camera.depth_camera)},
          {"depth_registered_to_color", camera.depth_registered_to_color},
          {"frames_subset", camera.frames_subset},
          {"T_color_depth", ToJson(camera.T_color_depth)},
          {"depth_unit_m", camera.depth_unit_m},
          {"camera_body", camera.camera_body},
          {"T_body_camera", ToJson(camera.T_body_camera)}};
}

CameraStreamInfo CameraFromJson(const nlohmann::json& json, const std::string& where) {
  CameraStreamInfo camera;
  camera.name = String(json, "name", where);
  camera.model = String(json, "model", where);
  camera.serial = String(json, "serial", where);
  camera.color_camera = PinholeFromJson(Field(json, "color_camera", where), where + ".color_camera");
  camera.depth_camera = PinholeFromJson(Field(json, "depth_camera", where), where + ".depth_camera");
  camera.depth_registered_to_color = Bool(json, "depth_registered_to_color", where);
  camera.frames_subset = json.contains("frames_subset") && Bool(json, "frames_subset", where);
  camera.T_color_depth = RigidFromJson(Field(json, "T_color_depth", where), where + ".T_color_depth");
  camera.depth_unit_m = Number(json, "depth_unit_m", where);
  camera.camera_body = String(json, "camera_body", where);
  camera.T_body_camera = RigidFromJson(Field(json, "T_body_camera", where), where + ".T_body_camera");
  return camera;
}

nlohmann::json ToJson(const TrackerStreamInfo& tracker) {
  return {{"name", tracker.name}, {"model", tracker.model}, {"serial", tracker.serial},
          {"frame", tracker.frame}, {"bodies", tracker.bodies}};
}

TrackerStreamInfo TrackerFromJson(const nlohmann::json& json, const std::string& where) {
  TrackerStreamInfo tracker;
  tracker.name = String(json, "name", where);
  tracker.model = String(json, "model", where);
  tracker.serial = String(json, "serial", where);
  tracker.frame = String(json, "frame", where);
  const auto& bodies = Field(json, "bodies", where);
  if (!bodies.is_array()) throw InputError(where, "field 'bodies' should be an array of names");
  for (const auto& body : bodies) {
    if (!body.is_string()) throw InputError(where, "field 'bodies' should hold strings only");
    tracker.bodies.push_back(body.get<std::string>());
  }
  return tracker;
}

}  // namespace

nlohmann::json ToJson(const Rigid3d& pose) {
  const Eigen::Vector3d& t = pose.translation();
  const Eigen::Vector4d q = pose.quat_wxyz();
  return {{"t_m", {t.x(), t.y(), t.z()}}, {"q_wxyz", {q[0], q[1], q[2], q[3]}}};
}

Rigid3d RigidFromJson(const nlohmann::json& json, const std::string& where) {
  const auto t = Numbers(json, "t_m", 3, where);
  const auto q = Numbers(json, "q_wxyz", 4, where);
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (!std::isfinite(norm) || std::abs(norm - 1.0) > 1e-3)
    throw InputError(where, Str("field 'q_wxyz' is not a unit quaternion (norm ", norm, ")"));
  for (double v : t)
    if (!std::isfinite(v)) throw InputError(where, "field 't_m' is not finite");
  return Rigid3d::FromQuatWxyz(q[0], q[1], q[2], q[3], {t[0], t[1], t[2]});
}

nlohmann::json ToJson(const PinholeCamera& camera) {
  return {{"width", camera.width}, {"height", camera.height}, {"fx", camera.fx}, {"fy", camera.fy},
          {"cx", camera.cx},       {"cy", camera.cy},         {"dist", camera.dist}};
}

PinholeCamera PinholeFromJson(const nlohmann::json& json, const std::string& where) {
  PinholeCamera camera;
  camera.width = static_cast<int>(Int(json, "width", where));
  camera.height = static_cast<int>(Int(json, "height", where));
  camera.fx = Number(json, "fx", where);
  camera.fy = Number(json, "fy", where);
  camera.cx = Number(json, "cx", where);
  camera.cy = Number(json, "cy", where);
  const auto dist = Numbers(json, "dist", 8, where);
  std::copy(dist.begin(), dist.end(), camera.dist.begin());
  return camera;
}

nlohmann::json ToJson(const ClockFit& fit) {
  return {{"ticks_origin", fit.ticks_origin}, {"offset_ns", fit.offset_ns},
          {"ns_per_tick", fit.ns_per_tick},   {"residual_rms_ns", fit.residual_rms_ns},
          {"residual_max_ns", fit.residual_max_ns}, {"samples", fit.samples},
          {"inliers", fit.inliers},           {"iterations", fit.iterations}};
}

ClockFit ClockFitFromJson(const nlohmann::json& json, const std::string& where) {
  ClockFit fit;
  fit.ticks_origin = Int(json, "ticks_origin", where);
  fit.offset_ns = Number(json, "offset_ns", where);
  fit.ns_per_tick = Number(json, "ns_per_tick", where);
  fit.residual_rms_ns = Number(json, "residual_rms_ns", where);
  fit.residual_max_ns = Number(json, "residual_max_ns", where);
  fit.samples = static_cast<int>(Int(json, "samples", where));
  fit.inliers = static_cast<int>(Int(json, "inliers", where));
  fit.iterations = static_cast<int>(Int(json, "iterations", where));
  return fit;
}

void SessionManifest::check() const {
  std::set<std::string> names;
  for (size_t i = 0; i < cameras.size(); ++i) {
    const auto& camera = cameras[i];
    const std::string where = Str("cameras[", i, "]");
    CheckStreamName(camera.name, where + ".name");
    if (!names.insert(camera.name).second) throw InputError(where, Str("duplicate stream name '", camera.name, "'"));
    if (!(camera.depth_unit_m > 0.0) || !std::isfinite(camera.depth_unit_m))
      throw InputError(where + ".depth_unit_m", Str("must be positive, is ", camera.depth_unit_m));
    camera.color_camera.check();
    if (camera.depth_camera.width != 0 || camera.depth_camera.height != 0) camera.depth_camera.check();
  }
  for (size_t i = 0; i < trackers.size(); ++i) {
    const auto& tracker = trackers[i];
    const std::string where = Str("trackers[", i, "]");
    CheckStreamName(tracker.name, where + ".name");
    if (!names.insert(tracker.name).second) throw InputError(where, Str("duplicate stream name '", tracker.name, "'"));
    const bool in_camera = tracker.frame.rfind("camera:", 0) == 0 && FindCamera(tracker.frame.substr(7));
    if (tracker.frame != "tracker" && !in_camera)
      throw InputError(where + ".frame", Str("'", tracker.frame, "' is neither \"tracker\" nor \"camera:<camera name>\""));
    std::set<std::string> bodies;
    for (const auto& body : tracker.bodies)
      if (body.empty() || !bodies.insert(body).second)
        throw InputError(where + ".bodies", Str("body name '", body, "' is empty or repeated"));
  }
}

const CameraStreamInfo* SessionManifest::FindCamera(const std::string& name) const {
  for (const auto& camera : cameras)
    if (camera.name == name) return &camera;
  return nullptr;
}

const TrackerStreamInfo* SessionManifest::FindTracker(const std::string& name) const {
  for (const auto& tracker : trackers)
    if (tracker.name == name) return &tracker;
  return nullptr;
}

nlohmann::json ToJson(const SessionManifest& manifest) {
  nlohmann::json json = {{"format", "mocaplabel-session"},
                         {"format_version", manifest.format_version},
                         {"software_version", manifest.software_version},
                         {"created_utc", manifest.created_utc},
                         {"source", manifest.source},
                         {"complete", manifest.complete},
                         {"cameras", nlohmann::json::array()},
                         {"trackers", nlohmann::json::array()},
                         {"clock_fits", nlohmann::json::object()},
                         {"extra", manifest.extra}};
  for (const auto& camera : manifest.cameras) json["cameras"].push_back(ToJson(camera));
  for (const auto& tracker : manifest.trackers) json["trackers"].push_back(ToJson(tracker));
  for (const auto& [device, fit] : manifest.clock_fits) json["clock_fits"][device] = ToJson(fit);
  if (!manifest.stream_records.empty()) json["stream_records"] = manifest.stream_records;
  return json;
}

SessionManifest ManifestFromJson(const nlohmann::json& json, const std::string& where) {
  if (StringOr(json, "format", "", where) != "mocaplabel-session")
    throw InputError(where, "field 'format' should be \"mocaplabel-session\": not a mocaplabel session manifest");
  SessionManifest manifest;
  manifest.format_version = static_cast<int>(Int(json, "format_version", where));
  if (manifest.format_version != kSessionFormatVersion)
    throw InputError(where, Str("field 'format_version' is ", manifest.format_version, "; this mocaplabel reads version ",
                                kSessionFormatVersion, " only (a newer mocaplabel may read it)"));
  manifest.software_version = String(json, "software_version", where);
  manifest.created_utc = String(json, "created_utc", where);
  manifest.source = String(json, "source", where);
  manifest.complete = Bool(json, "complete", where);
  if (json.contains("stream_records")) {
    const auto& counts = json["stream_records"];
    if (!counts.is_object()) throw InputError(where, "field 'stream_records' should be an object of record counts");
    for (const auto& [file, count] : counts.items()) {
      if (!count.is_number_integer() || count.get<int64_t>() < 0)
        throw InputError(where, Str("field 'stream_records'.'", file, "' should be a record count (an integer >= 0)"));
      manifest.stream_records[file] = count.get<int64_t>();
    }
  }
  const auto& cameras = Field(json, "cameras", where);
  const auto& trackers = Field(json, "trackers", where);
  const auto& fits = Field(json, "clock_fits", where);
  if (!cameras.is_array() || !trackers.is_array() || !fits.is_object())
    throw InputError(where, "fields 'cameras' and 'trackers' should be arrays, 'clock_fits' an object");
  for (size_t i = 0; i < cameras.size(); ++i)
    manifest.cameras.push_back(CameraFromJson(cameras[i], Str(where, ": cameras[", i, "]")));
  for (size_t i = 0; i < trackers.size(); ++i)
    manifest.trackers.push_back(TrackerFromJson(trackers[i], Str(where, ": trackers[", i, "]")));
  for (const auto& [device, fit] : fits.items())
    manifest.clock_fits[device] = ClockFitFromJson(fit, Str(where, ": clock_fits.", device));
  if (json.contains("extra")) manifest.extra = json["extra"];
  try {
    manifest.check();
  } catch (const InputError& e) {
    throw InputError(where, e.what());
  }
  return manifest;
}

void SaveManifest(const fs::path& session_dir, const SessionManifest& manifest) {
  WriteFileAtomically(session_dir / "manifest.json", ToJson(manifest).dump(2) + "\n");
}

SessionManifest LoadManifest(const fs::path& session_dir) {
  if (!fs::is_directory(session_dir))
    throw InputError(session_dir.string(), "no such session folder");
  const fs::path path = session_dir / "manifest.json";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open the session manifest (is this a session folder?)");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(Str(path.string(), ":byte ", e.byte), Str("not valid JSON: ", e.what()));
  } catch (const nlohmann::json::exception& e) {  // a number beyond double's range (out_of_range.406), found by tests/fuzz
    throw InputError(path.string(), Str("not valid JSON: ", e.what()));
  }
  return ManifestFromJson(json, path.string());
}

fs::path CameraStreamFile(const std::string& camera) { return fs::path("cameras") / camera / "frames.jsonl"; }

fs::path TrackerStreamFile(const std::string& tracker) { return fs::path("trackers") / tracker / "samples.jsonl"; }

std::vector<fs::path> SessionStreamFiles(const SessionManifest& manifest) {
  std::vector<fs::path> files = {"manifest.json"};
  for (const CameraStreamInfo& c : manifest.cameras) files.push_back(CameraStreamFile(c.name));
  for (const TrackerStreamInfo& t : manifest.trackers) files.push_back(TrackerStreamFile(t.name));
  return files;
}

}  // namespace mocap
