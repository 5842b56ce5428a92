#include "session/records.h"

#include <cstdio>
#include <cstdlib>

#include "core/check.h"
#include "session/json_fields.h"
#include "session/manifest.h"

namespace mocap {
using namespace json_fields;

namespace {
constexpr int64_t kMaxDepthColourGapNs = 1'000'000'000;
}  // namespace

std::string FrameFileStem(int64_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06lld", static_cast<long long>(index));
  return name;
}

bool CarriesPose(PoseStatus status) { return status != PoseStatus::kMissing && status != PoseStatus::kDisabled; }

nlohmann::json ToJson(const CameraFrameRecord& record) {
  nlohmann::json json = {{"frame", record.frame}, {"device_ticks", record.device_ticks},
                         {"stamp_ns", record.stamp_ns}, {"source_id", record.source_id}};
  if (record.depth_stamp_ns != 0) json["depth_stamp_ns"] = record.depth_stamp_ns;
  if (record.has_color()) json["color"] = record.color_file;
  if (record.has_depth()) json["depth"] = record.depth_file;
  return json;
}

CameraFrameRecord CameraFrameRecordFromJson(const nlohmann::json& json, const std::string& where) {
  CameraFrameRecord record;
  record.frame = Int(json, "frame", where);
  record.device_ticks = Int(json, "device_ticks", where);
  record.stamp_ns = Int(json, "stamp_ns", where);
  record.depth_stamp_ns = IntOr(json, "depth_stamp_ns", 0, where);
  // A depth exposure is paired with the colour one it was taken beside; seconds apart is a corrupt record.
  if (record.depth_stamp_ns != 0 && std::llabs(record.depth_stamp_ns - record.stamp_ns) > kMaxDepthColourGapNs)
    throw InputError(where, Str("depth_stamp_ns is ", (record.depth_stamp_ns - record.stamp_ns) / 1000000,
                                " ms from stamp_ns (at most 1000 ms)"));
  record.source_id = String(json, "source_id", where);
  record.color_file = StringOr(json, "color", "", where);
  record.depth_file = StringOr(json, "depth", "", where);
  for (const std::string* file : {&record.color_file, &record.depth_file})
    if (file->find("..") != std::string::npos || (!file->empty() && file->front() == '/'))
      throw InputError(where, Str("image path '", *file, "' leaves the camera folder"));
  return record;
}

nlohmann::json ToJson(const TrackerRecord& record) {
  nlohmann::json json = {{"body", record.body},
                         {"status", std::string(ToString(record.status))},
                         {"device_frame", record.device_frame},
                         {"device_ticks", record.device_ticks},
                         {"stamp_ns", record.stamp_ns},
                         {"rms_error_m", record.rms_error_m},
                         {"port_status", record.port_status}};
  if (CarriesPose(record.status)) json["T_frame_body"] = ToJson(record.T_frame_body);
  return json;
}

TrackerRecord TrackerRecordFromJson(const nlohmann::json& json, const std::string& where) {
  TrackerRecord record;
  record.body = String(json, "body", where);
  try {
    record.status = PoseStatusFromString(String(json, "status", where));
  } catch (const InputError& e) {
    throw InputError(where, Str("field 'status': ", e.what()));
  }
  record.device_frame = Int(json, "device_frame", where);
  record.device_ticks = Int(json, "device_ticks", where);
  record.stamp_ns = Int(json, "stamp_ns", where);
  record.rms_error_m = Number(json, "rms_error_m", where);
  const int64_t port_status = Int(json, "port_status", where);
  if (port_status < 0 || port_status > 0xffffffffLL)
    throw InputError(where, Str("field 'port_status' is out of the 32-bit range: ", port_status));
  record.port_status = static_cast<uint32_t>(port_status);
  if (CarriesPose(record.status))
    record.T_frame_body = RigidFromJson(Field(json, "T_frame_body", where), where + ": T_frame_body");
  return record;
}

nlohmann::json ToJson(const EventRecord& record) {
  return {{"stamp_ns", record.stamp_ns}, {"kind", record.kind}, {"stream", record.stream},
          {"detail", record.detail}};
}

EventRecord EventRecordFromJson(const nlohmann::json& json, const std::string& where) {
  EventRecord record;
  record.stamp_ns = Int(json, "stamp_ns", where);
  record.kind = String(json, "kind", where);
  record.stream = String(json, "stream", where);
  record.detail = String(json, "detail", where);
  return record;
}

}  // namespace mocap
