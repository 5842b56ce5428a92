#include "capture/daemon/recorder.h"

#include <algorithm>

#include "core/check.h"
#include "core/log.h"

namespace mocap::capture {

void RecorderOptions::check() const {
  if (session_dir.empty()) throw InputError("RecorderOptions.session_dir", "is empty: name the session folder");
  if (frame_queue < 1 || frame_queue > 4096) throw InputError("RecorderOptions.frame_queue", "must be in 1..4096");
  if (sample_queue < 1 || sample_queue > 1'000'000)
    throw InputError("RecorderOptions.sample_queue", "must be in 1..1000000");
  if (drop_event_interval_ms < 1) throw InputError("RecorderOptions.drop_event_interval_ms", "must be >= 1");
  writer.check();
}

nlohmann::json RecorderSummary::ToJson() const {
  nlohmann::json streams_json = nlohmann::json::object();
  for (const auto& [name, c] : streams)
    streams_json[name] = {{"received", c.received}, {"written", c.written}, {"dropped", c.dropped}};
  return {{"session", session_dir.string()}, {"complete", complete},     {"error", error},
          {"streams", streams_json},         {"events_written", events_written},
          {"events_dropped", events_dropped}, {"duration_s", duration_ns * 1e-9}};
}

std::unique_ptr<Recorder> Recorder::Start(const RecorderOptions& options, const SessionManifest& manifest) {
  options.check();
  auto writer = SessionWriter::Create(options.session_dir, manifest, options.writer);
  std::unique_ptr<Recorder> recorder(new Recorder(options, std::move(writer)));
  for (const auto& camera : manifest.cameras) {
    recorder->streams_[camera.name];
    recorder->frames_[camera.name] = std::make_unique<BoundedQueue<CapturedFrame>>(static_cast<size_t>(options.frame_queue));
  }
  for (const auto& tracker : manifest.trackers) recorder->streams_[tracker.name];
  for (auto& [camera, queue] : recorder->frames_)
    recorder->frame_threads_.emplace_back([r = recorder.get(), name = camera, q = queue.get()] { r->FrameLoop(name, *q); });
  recorder->record_thread_ = std::thread([r = recorder.get()] { r->RecordLoop(); });
  return recorder;
}

Recorder::Recorder(const RecorderOptions& options, std::unique_ptr<SessionWriter> writer)
    : options_(options),
      writer_(std::move(writer)),
      records_(static_cast<size_t>(options.sample_queue)),
      start_ns_(MonotonicNowNs()) {}

Recorder::~Recorder() { Stop(); }

StreamCounters& Recorder::counters(const std::string& stream) { return streams_[stream]; }

void Recorder::PushFrame(CapturedFrame&& frame) {
  const std::string camera = frame.camera;
  const int64_t stamp_ns = frame.record.stamp_ns;
  {
    std::lock_guard lock(mutex_);
    ++counters(camera).received;
  }
  const auto queue = frames_.find(camera);
  if (queue == frames_.end()) {  // the writer would refuse it: as a write error, it stops the session
    Fail("camera '" + camera + "' is not in the session manifest");
    CountDrop(camera, stamp_ns);
    return;
  }
  if (!queue->second->TryPush(std::move(frame))) CountDrop(camera, stamp_ns);
}

size_t Recorder::frame_queue_depth() const {
  size_t depth = 0;
  for (const auto& [camera, queue] : frames_) depth += queue->size();
  return depth;
}

size_t Recorder::frame_queue_depth(const std::string& camera) const {
  const auto queue = frames_.find(camera);
  return queue == frames_.end() ? 0 : queue->second->size();
}

void Recorder::PushSample(CapturedSample&& sample) {
  const std::string tracker = sample.tracker;
  const int64_t stamp_ns = sample.record.stamp_ns;
  {
    std::lock_guard lock(mutex_);
    ++counters(tracker).received;
  }
  if (!records_.TryPush(RecordItem(std::move(sample)))) CountDrop(tracker, stamp_ns);
}

void Recorder::PushEvent(EventRecord&& event) {
  if (records_.TryPush(RecordItem(std::move(event)))) return;
  std::lock_guard lock(mutex_);
  ++events_dropped_;
}

// Counted at once; written as one "drop" event per stream per interval carrying the count (by the
// writer threads, which also print it for whoever watches the daemon), and by Stop() at the latest.
void Recorder::CountDrop(const std::string& stream, int64_t /*stamp_ns*/) {
  std::lock_guard lock(mutex_);
  ++counters(stream).dropped;
  ++unreported_drops_[stream];
}

void Recorder::FlushDropEvents(bool final_flush) {
  std::map<std::string, int64_t> pending;
  const int64_t now_ns = MonotonicNowNs();
  {
    std::lock_guard lock(mutex_);
    if (failed_ || unreported_drops_.empty()) return;
    if (!final_flush && now_ns - last_drop_flush_ns_ < int64_t{options_.drop_event_interval_ms} * 1'000'000) return;
    last_drop_flush_ns_ = now_ns;
    pending.swap(unreported_drops_);
  }
  for (const auto& [stream, n] : pending) {
    Log().warn("capture: {}: {} item(s) dropped, the session writer is behind", stream, n);
    EventRecord event{now_ns, "drop", stream,
                      Str(n, " item(s) dropped: the session writer fell behind and the queue was full")};
    if (final_flush) {
      writer_->WriteEvent(event);
      std::lock_guard lock(mutex_);
      ++events_written_;
    } else if (!records_.TryPush(RecordItem(std::move(event)))) {
      std::lock_guard lock(mutex_);
      unreported_drops_[stream] += n;  // no room now: with the next flush
    }
  }
}

void Recorder::Fail(const std::string& message) {
  std::lock_guard lock(mutex_);
  if (failed_) return;
  error_ = message;
  failed_ = true;
  Log().error("capture: session {} stopped: {}", options_.session_dir.string(), message);
}

void Recorder::WriteFrame(CapturedFrame& frame) {
  if (frame.color_jpeg) writer_->WriteCameraFrameJpeg(frame.camera, frame.record, frame.color_jpeg, frame.depth);
  else writer_->WriteCameraFrame(frame.camera, frame.record, frame.color, frame.depth);
}

void Recorder::FrameLoop(const std::string& camera, BoundedQueue<CapturedFrame>& queue) {
  while (std::optional<CapturedFrame> frame = queue.Pop()) {
    if (failed_) {  // the session stopped on a write error: what is still queued is not written
      std::lock_guard lock(mutex_);
      ++counters(camera).dropped;
      continue;
    }
    try {
      WriteFrame(*frame);
      {
        std::lock_guard lock(mutex_);
        ++counters(camera).written;
        if (frame->record.device_ticks != 0) clocks_.Add(camera, frame->record.device_ticks, frame->record.stamp_ns);
      }
      FlushDropEvents(false);
    } catch (const std::exception& e) {
      Fail(e.what());
      std::lock_guard lock(mutex_);
      ++counters(camera).dropped;
    }
  }
}

void Recorder::WriteRecord(RecordItem& item) {
  if (auto* sample = std::get_if<CapturedSample>(&item)) {
    writer_->WriteTrackerSample(sample->tracker, sample->record);
    std::lock_guard lock(mutex_);
    ++counters(sample->tracker).written;
    if (sample->record.device_frame != 0) clocks_.Add(sample->tracker, sample->record.device_frame, sample->record.stamp_ns);
  } else {
    writer_->WriteEvent(std::get<EventRecord>(item));
    std::lock_guard lock(mutex_);
    ++events_written_;
  }
}

void Recorder::RecordLoop() {
  while (std::optional<RecordItem> item = records_.Pop()) {
    if (failed_) {
      std::lock_guard lock(mutex_);
      if (auto* sample = std::get_if<CapturedSample>(&*item)) ++counters(sample->tracker).dropped;
      else ++events_dropped_;
      continue;
    }
    try {
      WriteRecord(*item);
      FlushDropEvents(false);
    } catch (const std::exception& e) {
      Fail(e.what());
    }
  }
}

RecorderSummary Recorder::Stop() {
  bool already_stopped = false;
  {
    std::lock_guard lock(mutex_);
    already_stopped = stopped_;
    stopped_ = true;
  }
  if (already_stopped) return Snapshot();
  for (auto& [camera, queue] : frames_) queue->Stop();
  records_.Stop();
  for (std::thread& thread : frame_threads_) thread.join();
  frame_threads_.clear();
  if (record_thread_.joinable()) record_thread_.join();
  try {
    FlushDropEvents(true);
    if (!failed_) {
      for (const auto& [stream, fit] : clocks_.Fit()) writer_->UpdateClockFit(stream, fit);
      writer_->Close();
      std::lock_guard lock(mutex_);
      complete_ = true;
    }
  } catch (const std::exception& e) {
    Fail(e.what());
  }
  {
    std::lock_guard lock(mutex_);
    stop_ns_ = MonotonicNowNs();
  }
  return Snapshot();
}

RecorderSummary Recorder::Snapshot() const {
  std::lock_guard lock(mutex_);
  RecorderSummary summary;
  summary.session_dir = options_.session_dir;
  summary.complete = complete_;
  summary.error = error_;
  summary.streams = streams_;
  summary.events_written = events_written_;
  summary.events_dropped = events_dropped_;
  summary.duration_ns = (stop_ns_ != 0 ? stop_ns_ : MonotonicNowNs()) - start_ns_;
  return summary;
}

std::optional<std::string> Recorder::error() const {
  std::lock_guard lock(mutex_);
  if (!failed_) return std::nullopt;
  return error_;
}

// "frames" sums the cameras' queues (depth and capacity; the highest peak); "cameras" has each one.
nlohmann::json Recorder::QueueStatus() const {
  nlohmann::json cameras = nlohmann::json::object();
  size_t depth = 0, high_water = 0, capacity = 0;
  for (const auto& [camera, queue] : frames_) {
    const size_t d = queue->size(), h = queue->high_water(), c = queue->capacity();
    cameras[camera] = {{"depth", d}, {"high_water", h}, {"capacity", c}};
    depth += d;
    high_water = std::max(high_water, h);
    capacity += c;
  }
  return {{"frames", {{"depth", depth}, {"high_water", high_water}, {"capacity", capacity}}},
          {"cameras", cameras},
          {"records", {{"depth", records_.size()}, {"high_water", records_.high_water()}, {"capacity", records_.capacity()}}}};
}

}  // namespace mocap::capture
