// The polling thread of NdiClient: BX/TX at the tracker's rate, delivery, and reconnects.
#include <algorithm>

#include "capture/ndi/client.h"
#include "capture/ndi/convert.h"
#include "capture/ndi/tool_setup.h"

namespace mocap::ndi {

void NdiClient::PollLoop() {
  const auto period_ns = static_cast<int64_t>(1e9 / options_.poll_rate_hz);
  int failures = 0;
  int64_t next_ns = MonotonicNowNs();
  while (true) {
    try {
      PollOnce();
      failures = 0;
    } catch (const ReplyError& e) {
      Emit(e.kind() == ReplyError::Kind::kDeviceError ? TrackerEventKind::kDeviceError : TrackerEventKind::kReplyError,
           e.what());
      if (++failures >= options_.lost_after_failures) {
        Reconnect();
        failures = 0;
      }
    } catch (const TransportError& e) {
      Emit(TrackerEventKind::kReplyError, e.what());
      Reconnect();
      failures = 0;
    }
    SyncCounters();
    next_ns += period_ns;
    const int64_t now_ns = MonotonicNowNs();
    if (next_ns < now_ns) next_ns = now_ns;  // behind (slow reply, reconnect): do not burst
    if (!SleepFor(next_ns - now_ns)) return;
  }
}

void NdiClient::PollOnce() {
  if (!link_) throw TransportError("not connected");
  const TrackingReply reply = options_.use_bx ? link_->Bx(BxOptions(), options_.reply_timeout_ms)
                                              : link_->Tx(options_.reply_options, options_.reply_timeout_ms);
  Deliver(reply, MonotonicNowNs());
}

void NdiClient::Deliver(const TrackingReply& reply, int64_t stamp_ns) {
  const auto framed = std::find_if(reply.handles.begin(), reply.handles.end(),
                                   [](const HandleReport& h) { return h.has_port_status; });
  const bool has_frame = framed != reply.handles.end();
  const uint32_t frame = has_frame ? framed->frame_number : 0;
  {
    std::lock_guard lock(mutex_);
    ++stats_.replies;
    if (options_.skip_repeated_frames && has_frame && have_last_frame_ && frame == last_frame_ && !gap_pending_) {
      ++stats_.repeated_frames;
      return;
    }
    ++stats_.samples;
  }
  if (gap_pending_) {
    TrackerEvent gap{TrackerEventKind::kGap, stamp_ns, "", stamp_ns - last_sample_ns_, last_frame_, frame};
    gap.message = "tracker gap of " + std::to_string((stamp_ns - last_sample_ns_) / 1'000'000) + " ms, frames " +
                  std::to_string(last_frame_) + " -> " + std::to_string(frame);
    if (on_event_) on_event_(gap);
    gap_pending_ = false;
  }
  if (reply.system_status != last_system_status_) {
    Emit(TrackerEventKind::kSystemStatus, "system status " + std::to_string(reply.system_status) + ": " +
                                               (reply.system_status ? DescribeSystemStatus(reply.system_status) : "clear"));
    last_system_status_ = reply.system_status;
  }
  if (has_frame) {
    last_frame_ = frame;
    have_last_frame_ = true;
  }
  last_sample_ns_ = stamp_ns;
  TrackerSample sample{stamp_ns, reply.system_status, {}};
  const auto names = handles();
  for (const HandleReport& h : reply.handles) {
    BodySample body;
    const auto named = std::find_if(names.begin(), names.end(), [&](const auto& n) { return n.first == h.handle; });
    body.name = named != names.end() ? named->second : DefaultHandleName(h.handle);
    body.handle = h.handle;
    body.ndi_status = h.status;
    body.status = ToPoseStatus(h);
    body.frame_number = h.frame_number;
    body.port_status = h.port_status;
    if (options_.use_bx && (BxOptions() & reply_option::kToolMarkers) && h.status != HandleStatus::kDisabled)
      body.markers = static_cast<int>(h.markers_mm.size());
    if (const std::optional<Rigid3d> pose = ToRigid3d(h)) {
      body.T_tracker_body = *pose;
      body.has_pose = true;
      body.rms_error_m = RmsErrorM(h);
    }
    sample.bodies.push_back(std::move(body));
  }
  if (on_sample_) on_sample_(sample);
}

void NdiClient::Reconnect() {
  {
    std::lock_guard lock(mutex_);
    ++stats_.disconnects;
  }
  Emit(TrackerEventKind::kDisconnected, "lost the tracker" + (link_ ? " on " + link_->transport().Describe() : std::string()));
  DropLink();
  int backoff_ms = options_.reconnect_initial_ms;
  while (SleepFor(static_cast<int64_t>(backoff_ms) * 1'000'000)) {
    try {
      Connect();
      Setup();
      link_->Command(TstartCommand(), options_.init_timeout_ms);
      {
        std::lock_guard lock(mutex_);
        ++stats_.reconnects;
      }
      gap_pending_ = have_last_frame_ || last_sample_ns_ != 0;
      Emit(TrackerEventKind::kReconnected, "tracking again on " + link_->transport().Describe());
      return;
    } catch (const std::exception&) {
      DropLink();  // still down (or refusing): try again later
      backoff_ms = std::min(backoff_ms * 2, options_.reconnect_max_ms);
    }
  }
}

}  // namespace mocap::ndi
