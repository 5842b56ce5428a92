// rig.yaml's writer (rig.h).
#include "core/check.h"
#include "pipeline/rig.h"
#include "pipeline/yaml_write.h"

namespace mocap::pipeline {
namespace {

void EmitCamera(YAML::Emitter& out, const RigCameraCalibration& c) {
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << c.name;
  if (c.body) out << YAML::Key << "body" << YAML::Value << *c.body;
  if (c.T_body_camera) {
    out << YAML::Key << "T_body_camera" << YAML::Value;
    EmitPose(out, *c.T_body_camera);
  }
  if (c.intrinsics) {
    out << YAML::Key << "intrinsics" << YAML::Value;
    EmitIntrinsics(out, *c.intrinsics);
  }
  if (c.T_color_depth) {
    out << YAML::Key << "T_color_depth" << YAML::Value;
    EmitPose(out, *c.T_color_depth);
  }
  out << YAML::EndMap;
}

void EmitTracker(YAML::Emitter& out, const capture::NdiSourceOptions& t) {
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << t.stream << YAML::Key << "model" << YAML::Value << t.model;
  if (t.client.transport == ndi::NdiClientOptions::TransportKind::kTcp) {
    out << YAML::Key << "tcp" << YAML::Value << Str(t.client.host, ":", t.client.port);
  } else {
    out << YAML::Key << "serial" << YAML::Value << t.client.serial_device << YAML::Key << "baud" << YAML::Value
        << t.client.serial_baud;
  }
  out << YAML::Key << "rate_hz" << YAML::Value;
  EmitNumber(out, t.client.poll_rate_hz);
  out << YAML::Key << "protocol" << YAML::Value << (t.client.use_bx ? "bx" : "tx");
  if (t.replay) out << YAML::Key << "replay" << YAML::Value << true;
  if (!t.client.tools.empty()) {
    out << YAML::Key << "tools" << YAML::Value << YAML::BeginSeq;
    for (const ndi::ToolSpec& tool : t.client.tools)
      out << YAML::Flow << YAML::BeginMap << YAML::Key << "name" << YAML::Value << tool.name << YAML::Key << "rom"
          << YAML::Value << tool.rom_path << YAML::EndMap;
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
}

void EmitCaptureCamera(YAML::Emitter& out, const capture::CameraSourceOptions& camera) {
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << capture::StreamOf(camera);
  if (const auto* k2 = std::get_if<capture::Kinect2SourceOptions>(&camera)) {
    out << YAML::Key << "model" << YAML::Value << "kinect2";
    if (!k2->device.serial.empty()) out << YAML::Key << "serial" << YAML::Value << k2->device.serial;
    if (!k2->device.pipeline.empty()) out << YAML::Key << "pipeline" << YAML::Value << k2->device.pipeline;
  } else {
    const auto& k1 = std::get<capture::Kinect1SourceOptions>(camera);
    out << YAML::Key << "model" << YAML::Value << "kinect1";
    if (k1.device.camera_serial.empty())
      out << YAML::Key << "index" << YAML::Value << k1.device.device_index;
    else
      out << YAML::Key << "serial" << YAML::Value << k1.device.camera_serial;
  }
  out << YAML::EndMap;
}

void EmitCapture(YAML::Emitter& out, const RigCapture& c) {
  out << YAML::BeginMap << YAML::Key << "sessions_dir" << YAML::Value << c.sessions_dir;
  out << YAML::Key << "control" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "bind" << YAML::Value
      << c.control.bind << YAML::Key << "port" << YAML::Value << c.control.port << YAML::EndMap;
  out << YAML::Key << "frame_queue" << YAML::Value << c.frame_queue << YAML::Key << "sample_queue" << YAML::Value
      << c.sample_queue;
  if (c.tracker) {
    out << YAML::Key << "tracker" << YAML::Value;
    EmitTracker(out, *c.tracker);
  }
  // One camera as `camera:` (as rigs were written before lists), several as `cameras:`.
  if (c.cameras.size() == 1) {
    out << YAML::Key << "camera" << YAML::Value;
    EmitCaptureCamera(out, c.cameras.front());
  } else if (!c.cameras.empty()) {
    out << YAML::Key << "cameras" << YAML::Value << YAML::BeginSeq;
    for (const capture::CameraSourceOptions& camera : c.cameras) EmitCaptureCamera(out, camera);
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
}

}  // namespace

std::string EmitRig(const Rig& rig, const std::string& comment) {
  rig.check(rig.file.empty() ? "rig" : rig.file.string());
  YAML::Emitter out;
  if (!comment.empty()) out << YAML::Comment(comment) << YAML::Newline;
  out << YAML::BeginMap << YAML::Key << "name" << YAML::Value << rig.name;
  out << YAML::Key << "tracker_latency_ms" << YAML::Value;
  EmitNumber(out, static_cast<double>(rig.tracker_latency_ns) * 1e-6);
  out << YAML::Key << "cameras" << YAML::Value << YAML::BeginSeq;
  for (const RigCameraCalibration& c : rig.cameras) EmitCamera(out, c);
  out << YAML::EndSeq;
  if (rig.capture) {
    out << YAML::Key << "capture" << YAML::Value;
    EmitCapture(out, *rig.capture);
  }
  out << YAML::EndMap;
  MOCAP_CHECK(out.good(), "YAML emitter: ", out.GetLastError());
  return std::string(out.c_str()) + "\n";
}

void WriteRig(const Rig& rig, const std::filesystem::path& path, const std::string& comment) {
  WriteTextAtomically(path, EmitRig(rig, comment));
}

}  // namespace mocap::pipeline
