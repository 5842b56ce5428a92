#include <cmath>
#include <mutex>
#include <set>

#include "capture/daemon/sources.h"
#include "core/check.h"

namespace mocap::capture {

void NdiSourceOptions::check() const {
  if (stream.empty()) throw InputError("tracker.stream", "is empty: name the tracker stream");
  if (!(no_pose_warning_s > 0)) throw InputError("tracker.no_pose_warning_s", Str(no_pose_warning_s, " must be > 0"));
  client.check();
}

namespace {

// Session event kind of a client event (sources.h).
const char* EventKind(ndi::TrackerEventKind kind) {
  switch (kind) {
    case ndi::TrackerEventKind::kGap: return "gap";
    case ndi::TrackerEventKind::kReconnected: return "reconnect";
    case ndi::TrackerEventKind::kDisconnected:
    case ndi::TrackerEventKind::kReplyError:
    case ndi::TrackerEventKind::kDeviceError: return "error";
    case ndi::TrackerEventKind::kConnected:
    case ndi::TrackerEventKind::kSystemStatus: return "note";
  }
  return "note";
}

class NdiSource final : public CaptureSource {
 public:
  explicit NdiSource(const NdiSourceOptions& options) : CaptureSource(options.stream), options_(options) {
    options_.check();
  }
  ~NdiSource() override { Close(); }

  StreamInfo stream_info() const override {
    std::lock_guard lock(mutex_);
    TrackerStreamInfo info;
    info.name = name();
    info.model = options_.model;
    info.frame = "tracker";
    info.bodies = bodies_;
    return info;
  }

  nlohmann::json device_status() const override {
    const ndi::NdiClientStats s = client_ ? client_->stats() : ndi::NdiClientStats{};
    std::lock_guard lock(mutex_);
    return {{"kind", "ndi"},
            {"endpoint", endpoint()},
            {"connected", connected_},
            {"replies", s.replies},
            {"samples", s.samples},
            {"repeated_frames", s.repeated_frames},
            {"crc_errors", s.crc_errors},
            {"malformed_replies", s.malformed_replies},
            {"timeouts", s.timeouts},
            {"device_errors", s.device_errors},
            {"disconnects", s.disconnects},
            {"reconnects", s.reconnects},
            {"replay", options_.replay}};
  }

  bool starts_with_session() const override { return options_.replay; }

 private:
  std::string endpoint() const {
    if (options_.client.transport == ndi::NdiClientOptions::TransportKind::kSerial) return options_.client.serial_device;
    return Str(options_.client.host, ":", options_.client.port);
  }

  void DoOpen() override {
    client_ = std::make_unique<ndi::NdiClient>(
        options_.client, [this](const ndi::TrackerSample& s) { OnSample(s); },
        [this](const ndi::TrackerEvent& e) { OnEvent(e); });
    client_->Open();
    std::lock_guard lock(mutex_);
    for (const auto& [handle, body] : client_->handles()) bodies_.push_back(body);
    connected_ = true;
  }
  void DoStart(CaptureSink* sink) override {
    if (client_->state() == ndi::NdiClient::State::kClosed) {  // stopped before: connect again
      client_.reset();
      {
        std::lock_guard lock(mutex_);
        bodies_.clear();
      }
      DoOpen();
    }
    sink_.store(sink);
    client_->StartStreaming();
  }
  void DoStop() override {
    // The client has no pause: closing stops its polling thread; a later Start() connects again.
    client_->Close();
    sink_.store(nullptr);
  }
  void DoClose() override {
    if (client_) client_->Close();
  }

  void OnSample(const ndi::TrackerSample& sample) {
    CaptureSink* sink = sink_.load();
    if (!sink) return;
    WatchPoses(sample, *sink);
    for (const ndi::BodySample& body : sample.bodies) {
      CapturedSample out;
      out.tracker = name();
      out.record.body = body.name;
      out.record.status = body.status;
      out.record.device_frame = body.frame_number;
      out.record.stamp_ns = sample.host_stamp_ns;
      if (CarriesPose(body.status) && body.has_pose) out.record.T_frame_body = body.T_tracker_body;
      else if (CarriesPose(body.status)) out.record.status = PoseStatus::kMissing;
      out.record.rms_error_m = body.rms_error_m;
      out.record.port_status = body.port_status;
      out.markers = body.markers;
      sink->PushSample(std::move(out));
    }
  }

  // Polling thread only. Silence is not an answer: MISSING bodies forever (a replay past its end, tools
  // covered) get one "warning", so the session says why it has no poses.
  void WatchPoses(const ndi::TrackerSample& sample, CaptureSink& sink) {
    bool any_pose = false;
    for (const ndi::BodySample& body : sample.bodies) any_pose = any_pose || (HasPose(body.status) && body.has_pose);
    if (any_pose || last_pose_ns_ == 0) {
      if (any_pose && warned_no_pose_)
        sink.PushEvent({sample.host_stamp_ns, "note", name(),
                        Str("poses again after ", (sample.host_stamp_ns - last_pose_ns_) * 1e-9, " s without any")});
      last_pose_ns_ = sample.host_stamp_ns;
      warned_no_pose_ = false;
      return;
    }
    const int64_t without_ns = sample.host_stamp_ns - last_pose_ns_;
    if (warned_no_pose_ || without_ns < std::llround(options_.no_pose_warning_s * 1e9)) return;
    warned_no_pose_ = true;
    sink.PushEvent({sample.host_stamp_ns, "warning", name(),
                    Str("no body has had a pose for ", without_ns * 1e-9, " s (every tool hidden or out of the "
                        "volume, or an NDI emulator whose replay has ended)")});
  }

  void OnEvent(const ndi::TrackerEvent& event) {
    {
      std::lock_guard lock(mutex_);
      if (event.kind == ndi::TrackerEventKind::kDisconnected) connected_ = false;
      if (event.kind == ndi::TrackerEventKind::kReconnected) connected_ = true;
    }
    CaptureSink* sink = sink_.load();
    if (!sink) return;
    std::string detail = event.message;
    if (event.kind == ndi::TrackerEventKind::kGap)
      detail = Str("no samples for ", event.gap_ns * 1e-9, " s; last frame before ", event.last_frame_before,
                   ", first after ", event.first_frame_after, detail.empty() ? "" : "; ", detail);
    sink->PushEvent({event.host_stamp_ns, EventKind(event.kind), name(), detail});
  }

  NdiSourceOptions options_;
  std::unique_ptr<ndi::NdiClient> client_;
  std::atomic<CaptureSink*> sink_{nullptr};
  mutable std::mutex mutex_;
  std::vector<std::string> bodies_;
  bool connected_ = false;
  int64_t last_pose_ns_ = 0;     // polling thread: the last sample with a pose (or the first sample)
  bool warned_no_pose_ = false;  // polling thread
};

}  // namespace

std::unique_ptr<CaptureSource> CreateNdiSource(const NdiSourceOptions& options) {
  return std::make_unique<NdiSource>(options);
}

}  // namespace mocap::capture
