#include "pipeline/rig.h"

#include <cmath>
#include <set>

#include "core/check.h"
#include "pipeline/yaml_read.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

RigCameraCalibration ParseCamera(const YamlDoc& doc, const YAML::Node& node, size_t index) {
  const YamlMap map(doc, node, Str("camera ", index + 1), {"name", "body", "T_body_camera", "intrinsics", "T_color_depth"});
  RigCameraCalibration c;
  c.name = map.Get<std::string>("name");
  const std::string what = Str("camera '", c.name, "'");
  if (map.Has("intrinsics")) c.intrinsics = Intrinsics(doc, map["intrinsics"], what + " intrinsics");
  if (map.Has("body")) c.body = map.Get<std::string>("body");
  if (map.Has("T_body_camera")) c.T_body_camera = Pose(doc, map["T_body_camera"], "T_body_camera");
  if (map.Has("T_color_depth")) c.T_color_depth = Pose(doc, map["T_color_depth"], "T_color_depth");
  return c;
}

/// "host:port" onto the NDI client's TCP fields.
void ParseEndpoint(const YamlMap& map, ndi::NdiClientOptions& client) {
  const std::string endpoint = map.Get<std::string>("tcp");
  const size_t colon = endpoint.rfind(':');
  if (colon == std::string::npos || colon == 0) map.Fail("tcp", "must be HOST:PORT, e.g. 192.168.1.50:8765");
  client.host = endpoint.substr(0, colon);
  try {
    size_t used = 0;
    client.port = std::stoi(endpoint.substr(colon + 1), &used);
    if (used != endpoint.size() - colon - 1) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    map.Fail("tcp", Str("'", endpoint, "': the port is not a number"));
  }
}

capture::NdiSourceOptions ParseTracker(const YamlDoc& doc, const YAML::Node& node) {
  const YamlMap map(doc, node, "capture.tracker",
                    {"name", "model", "tcp", "serial", "baud", "rate_hz", "protocol", "tools", "replay"});
  capture::NdiSourceOptions t;
  t.stream = map.Get<std::string>("name", t.stream);
  t.model = map.Get<std::string>("model", t.model);
  if (map.Has("tcp") == map.Has("serial")) throw InputError(map.Where(), "capture.tracker: give either tcp: HOST:PORT or serial: DEVICE");
  if (map.Has("tcp")) {
    ParseEndpoint(map, t.client);
    if (map.Has("baud")) map.Fail("baud", "is for serial trackers only");
  } else {
    t.client.transport = ndi::NdiClientOptions::TransportKind::kSerial;
    t.client.serial_device = map.Get<std::string>("serial");
    t.client.serial_baud = map.Get<int>("baud", t.client.serial_baud);
  }
  t.client.poll_rate_hz = map.Get<double>("rate_hz", t.client.poll_rate_hz);
  const std::string protocol = map.Get<std::string>("protocol", "bx");
  if (protocol != "bx" && protocol != "tx") map.Fail("protocol", "must be bx or tx");
  t.client.use_bx = protocol == "bx";
  t.replay = map.Get<bool>("replay", false);
  if (map.Has("tools")) {
    if (!map["tools"].IsSequence()) map.Fail("tools", "must be a list of {name, rom}");
    for (const auto& tool : map["tools"]) {
      const YamlMap m(doc, tool, "a capture.tracker tool", {"name", "rom"});
      t.client.tools.push_back({m.Get<std::string>("name"), m.Get<std::string>("rom", ""), ndi::ToolMode::kDynamic});
    }
  }
  return t;
}

capture::CameraSourceOptions ParseCaptureCamera(const YamlDoc& doc, const YAML::Node& node, const std::string& what) {
  const YamlMap map(doc, node, what, {"name", "model", "index", "serial", "pipeline"});
  const std::string model = map.Get<std::string>("model", "kinect1");
  if (model == "kinect2") {
    capture::Kinect2SourceOptions c;
    c.stream = map.Get<std::string>("name", c.stream);
    c.device.serial = map.Get<std::string>("serial", "");
    c.device.pipeline = map.Get<std::string>("pipeline", "");
    if (map.Has("index")) map.Fail("index", "a Kinect2 is chosen by serial: (libfreenect2 has no index)");
    return c;
  }
  if (model != "kinect1") map.Fail("model", Str("'", model, "': the daemon drives kinect1 and kinect2"));
  capture::Kinect1SourceOptions c;
  c.stream = map.Get<std::string>("name", c.stream);
  c.device.device_index = map.Get<int>("index", 0);
  c.device.camera_serial = map.Get<std::string>("serial", "");
  if (map.Has("pipeline")) map.Fail("pipeline", "is for kinect2 (libfreenect2's packet pipeline)");
  return c;
}

RigCapture ParseCapture(const YamlDoc& doc, const YAML::Node& node) {
  const YamlMap map(doc, node, "capture", {"sessions_dir", "control", "frame_queue", "sample_queue", "tracker", "camera", "cameras"});
  RigCapture c;
  c.sessions_dir = map.Get<std::string>("sessions_dir", c.sessions_dir);
  if (map.Has("control")) {
    const YamlMap control(doc, map["control"], "capture.control", {"bind", "port"});
    c.control.bind = control.Get<std::string>("bind", c.control.bind);
    c.control.port = control.Get<int>("port", c.control.port);
  }
  c.frame_queue = map.Get<int>("frame_queue", c.frame_queue);
  c.sample_queue = map.Get<int>("sample_queue", c.sample_queue);
  if (c.frame_queue < 1) map.Fail("frame_queue", "must be >= 1");
  if (c.sample_queue < 1) map.Fail("sample_queue", "must be >= 1");
  if (map.Has("tracker")) c.tracker = ParseTracker(doc, map["tracker"]);
  if (map.Has("camera") && map.Has("cameras")) map.Fail("cameras", "give either camera: (one) or cameras: (a list), not both");
  if (map.Has("camera")) c.cameras.push_back(ParseCaptureCamera(doc, map["camera"], "capture.camera"));
  if (map.Has("cameras")) {
    if (!map["cameras"].IsSequence() || map["cameras"].size() == 0) map.Fail("cameras", "must be a list of cameras");
    for (size_t i = 0; i < map["cameras"].size(); ++i)
      c.cameras.push_back(ParseCaptureCamera(doc, map["cameras"][i], Str("capture camera ", i + 1)));
  }
  std::set<std::string> names;
  if (c.tracker) names.insert(c.tracker->stream);
  for (const auto& camera : c.cameras)
    if (!names.insert(capture::StreamOf(camera)).second)
      map.Fail(map.Has("cameras") ? "cameras" : "camera",
               Str("stream name '", capture::StreamOf(camera), "' is used twice: give each camera its own name"));
  if (!c.tracker && c.cameras.empty()) throw InputError(map.Where(), "capture: names neither a tracker nor a camera");
  return c;
}

Rig RigFromDoc(const YamlDoc& doc) {
  const YamlMap map(doc, doc.root, "the rig", {"name", "tracker_latency_ms", "cameras", "capture"});
  Rig rig;
  rig.file = doc.file;
  rig.name = map.Get<std::string>("name", fs::path(doc.file).stem().string());
  const double latency_ms = map.Get<double>("tracker_latency_ms", 0.0);
  if (std::abs(latency_ms) > 10'000) map.Fail("tracker_latency_ms", "is more than 10 s: is it in milliseconds?");
  rig.tracker_latency_ns = std::llround(latency_ms * 1e6);
  if (map.Has("cameras")) {
    if (!map["cameras"].IsSequence()) map.Fail("cameras", "must be a list");
    for (size_t i = 0; i < map["cameras"].size(); ++i) rig.cameras.push_back(ParseCamera(doc, map["cameras"][i], i));
  }
  if (map.Has("capture")) rig.capture = ParseCapture(doc, map["capture"]);
  rig.check(doc.file);
  return rig;
}

}  // namespace

const RigCameraCalibration* Rig::Find(const std::string& camera) const {
  for (const RigCameraCalibration& c : cameras)
    if (c.name == camera) return &c;
  return nullptr;
}

void Rig::check(const std::string& where) const {
  LabelRigOf(*this).check(where);
}

Rig ParseRig(const std::string& text, const std::string& file_name) { return RigFromDoc(ParseYaml(text, file_name)); }

Rig ReadRig(const fs::path& path) { return RigFromDoc(LoadYaml(path)); }

LabelRig LabelRigOf(const Rig& rig) {
  LabelRig out;
  out.name = rig.name;
  out.tracker_latency_ns = rig.tracker_latency_ns;
  for (const RigCameraCalibration& c : rig.cameras) out.cameras.push_back({c.name, c.intrinsics, c.body, c.T_body_camera, c.T_color_depth});
  return out;
}

CaptureOptions CaptureOptionsOf(const Rig& rig) {
  if (!rig.capture) throw InputError(rig.file.string(), "has no 'capture:' section (docs/capture.md)");
  const RigCapture& c = *rig.capture;
  CaptureOptions out;
  out.daemon.rig_name = rig.name;
  const fs::path sessions = c.sessions_dir;
  out.daemon.sessions_dir = sessions.is_absolute() ? sessions : rig.file.parent_path() / sessions;
  out.daemon.recorder.frame_queue = c.frame_queue;
  out.daemon.recorder.sample_queue = c.sample_queue;
  out.control.bind = c.control.bind;
  out.control.port = c.control.port;
  out.tracker = c.tracker;
  out.cameras = c.cameras;
  for (capture::CameraSourceOptions& camera : out.cameras)
    if (const RigCameraCalibration* calibrated = rig.Find(capture::StreamOf(camera)))
      capture::SetCalibration(camera, calibrated->intrinsics, calibrated->body.value_or(""),
                              calibrated->T_body_camera.value_or(Rigid3d()));
  return out;
}

}  // namespace mocap::pipeline
