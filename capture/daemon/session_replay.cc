#include "capture/daemon/session_replay.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <iterator>
#include <limits>
#include <mutex>
#include <thread>

#include "capture/kinect/camera_device.h"
#include "core/check.h"
#include "session/image_io.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

// JPEG colour is replayed as its bytes, as the camera that recorded it (a Kinect v2) handed it over, so a
// re-recording stores the same file; anything else is decoded.
std::shared_ptr<const std::vector<uint8_t>> ReadJpegAsStored(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open the image");
  auto bytes = std::make_shared<std::vector<uint8_t>>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (!IsWholeJpeg(*bytes)) throw InputError(path.string(), Str("JPEG is truncated or not a JPEG (", bytes->size(), " bytes)"));
  return bytes;
}

// The images of one record, decoded ahead of their time.
struct LoadedFrame {
  CapturedFrame frame;
  std::string error;  ///< why it could not be read ("" if it could)
};

// Two threads: a loader decodes records ahead into a bounded buffer (prefetch_frames), the player
// hands each to the sink at its due time. Decoding (a PNG of 640x480 takes 5-15 ms) thus overlaps the
// waiting, and a lead-in before the first due time fills the buffer.
class SessionCameraReplay final : public CaptureSource {
 public:
  SessionCameraReplay(const SessionCameraReplayOptions& options, SessionReader session, std::string camera)
      : CaptureSource(options.stream.empty() ? camera : options.stream),
        options_(options),
        session_(std::move(session)),
        camera_(std::move(camera)) {}
  ~SessionCameraReplay() override { Close(); }

  StreamInfo stream_info() const override {
    CameraStreamInfo info = *session_.manifest().FindCamera(camera_);
    info.name = name();
    return info;
  }

  nlohmann::json device_status() const override {
    std::lock_guard lock(mutex_);
    return {{"kind", "session replay"}, {"session", options_.session_dir.string()}, {"camera", camera_},
            {"frames", session_.frame_count(camera_)}, {"replayed", replayed_}, {"skipped", skipped_},
            {"unreadable", unreadable_}, {"late_frames", late_}, {"max_late_ms", max_late_ms_},
            {"max_load_ms", max_load_ms_}, {"finished", finished_}};
  }

 private:
  void DoOpen() override {}
  void DoClose() override {}
  void DoStart(CaptureSink* sink) override {
    stop_ = false;
    const int64_t start_host_ns = options_.start_host_ns > 0 ? options_.start_host_ns : MonotonicNowNs();
    SkipOverdue(start_host_ns);
    loader_ = std::thread([this] { LoadAhead(); });
    player_ = std::thread([this, sink, start_host_ns] { Play(sink, start_host_ns); });
  }
  void DoStop() override {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    if (player_.joinable()) player_.join();
    if (loader_.joinable()) loader_.join();
    std::lock_guard lock(mutex_);
    buffer_.clear();
    next_load_ = next_play_;
  }

  int64_t count() const { return session_.frame_count(camera_); }
  int64_t Due(int64_t index, int64_t start_host_ns) const {
    return start_host_ns + (session_.frame(camera_, index).record.stamp_ns - options_.origin_ns);
  }

  // Records already due when streaming starts are not replayed late: they are skipped and counted.
  void SkipOverdue(int64_t start_host_ns) {
    std::lock_guard lock(mutex_);
    while (next_play_ < count() && Due(next_play_, start_host_ns) < MonotonicNowNs()) ++next_play_, ++skipped_;
    next_load_ = next_play_;
  }

  LoadedFrame Decode(int64_t index) const {
    const CameraFrameEntry& entry = session_.frame(camera_, index);
    LoadedFrame loaded;
    loaded.frame.camera = name();
    loaded.frame.record = entry.record;
    loaded.frame.record.color_file.clear();
    loaded.frame.record.depth_file.clear();
    try {
      if (entry.color_present && session_.ColorPath(camera_, index).extension() == ".jpg")
        loaded.frame.color_jpeg = ReadJpegAsStored(session_.ColorPath(camera_, index));
      else if (entry.color_present)
        loaded.frame.color = session_.LoadColor(camera_, index);
      if (entry.depth_present) {
        DepthImage depth = session_.LoadDepth(camera_, index);
        loaded.frame.depth = cv::Mat(depth.height, depth.width, CV_32FC1, depth.data.data()).clone();
      }
      if (!loaded.frame.has_color() && loaded.frame.depth.empty()) loaded.error = "the record has no image";
    } catch (const std::exception& e) {
      loaded.error = e.what();
    }
    return loaded;
  }

  void LoadAhead() {
    for (;;) {
      int64_t index = 0;
      {
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return stop_ || buffer_.size() < static_cast<size_t>(options_.prefetch_frames); });
        if (stop_ || next_load_ >= count()) return;
        index = next_load_++;
      }
      const int64_t started_ns = MonotonicNowNs();
      LoadedFrame loaded = Decode(index);
      {
        std::lock_guard lock(mutex_);
        max_load_ms_ = std::max(max_load_ms_, static_cast<double>(MonotonicNowNs() - started_ns) * 1e-6);
        buffer_.push_back(std::move(loaded));
      }
      changed_.notify_all();
    }
  }

  // Sleeps until `due_ns` or a stop; false when stopped.
  bool WaitUntil(int64_t due_ns) const {
    for (int64_t now = MonotonicNowNs(); now < due_ns; now = MonotonicNowNs()) {
      if (stop_) return false;
      std::this_thread::sleep_for(std::chrono::nanoseconds(std::min<int64_t>(due_ns - now, 20'000'000)));
    }
    return !stop_;
  }

  void Play(CaptureSink* sink, int64_t start_host_ns) {
    for (;;) {
      LoadedFrame loaded;
      int64_t index = 0;
      {
        std::unique_lock lock(mutex_);
        if (next_play_ >= count()) {
          finished_ = true;
          return;
        }
        changed_.wait(lock, [&] { return stop_ || !buffer_.empty(); });
        if (stop_) return;
        loaded = std::move(buffer_.front());
        buffer_.pop_front();
        index = next_play_;
      }
      changed_.notify_all();
      const int64_t due_ns = Due(index, start_host_ns);
      if (!WaitUntil(due_ns)) return;
      Deliver(std::move(loaded), due_ns, sink);
      std::lock_guard lock(mutex_);
      ++next_play_;
    }
  }

  void Deliver(LoadedFrame&& loaded, int64_t due_ns, CaptureSink* sink) {
    const double late_ms = static_cast<double>(MonotonicNowNs() - due_ns) * 1e-6;
    if (!loaded.error.empty()) {
      sink->PushEvent({due_ns, "error", name(), Str("replayed frame ", loaded.frame.record.frame, ": ", loaded.error)});
      std::lock_guard lock(mutex_);
      ++unreadable_;
      return;
    }
    // The depth keeps its offset from the colour exposure it was paired with (Kinect v2).
    CameraFrameRecord& record = loaded.frame.record;
    if (record.depth_stamp_ns != 0) record.depth_stamp_ns = due_ns + (record.depth_stamp_ns - record.stamp_ns);
    record.stamp_ns = due_ns;
    sink->PushFrame(std::move(loaded.frame));
    std::lock_guard lock(mutex_);
    ++replayed_;
    if (late_ms > options_.late_after_ms) ++late_;
    max_late_ms_ = std::max(max_late_ms_, late_ms);
  }

  SessionCameraReplayOptions options_;
  SessionReader session_;
  std::string camera_;
  std::thread loader_, player_;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // guards everything below
  std::condition_variable changed_;
  std::deque<LoadedFrame> buffer_;
  int64_t next_load_ = 0, next_play_ = 0;
  int64_t replayed_ = 0, skipped_ = 0, unreadable_ = 0, late_ = 0;
  double max_late_ms_ = 0, max_load_ms_ = 0;
  bool finished_ = false;
};

}  // namespace

void SessionCameraReplayOptions::check() const {
  if (session_dir.empty()) throw InputError("session replay", "no session folder given");
  if (start_host_ns < 0) throw InputError("session replay", "start_host_ns must be >= 0 (0: when streaming starts)");
  if (!(late_after_ms >= 0)) throw InputError("session replay", "late_after_ms must be >= 0");
  if (prefetch_frames < 1) throw InputError("session replay", "prefetch_frames must be >= 1");
}

std::string OnlyCamera(const SessionManifest& manifest) {
  if (manifest.cameras.size() > 1) throw InputError("session", "has several cameras; name the one to replay");
  return manifest.cameras.empty() ? "" : manifest.cameras.front().name;
}

std::string OnlyTracker(const SessionManifest& manifest) {
  if (manifest.trackers.size() > 1) throw InputError("session", "has several trackers; name the one to replay");
  return manifest.trackers.empty() ? "" : manifest.trackers.front().name;
}

std::unique_ptr<CaptureSource> CreateSessionCameraReplay(const SessionCameraReplayOptions& options) {
  options.check();
  return CreateSessionCameraReplay(options, SessionReader::Open(options.session_dir));
}

std::unique_ptr<CaptureSource> CreateSessionCameraReplay(const SessionCameraReplayOptions& options, SessionReader session) {
  options.check();
  const std::string camera = options.camera.empty() ? OnlyCamera(session.manifest()) : options.camera;
  if (camera.empty() || !session.manifest().FindCamera(camera))
    throw InputError(options.session_dir.string(), Str("has no camera stream '", camera, "' to replay"));
  return std::make_unique<SessionCameraReplay>(options, std::move(session), camera);
}

std::vector<ndi::RecordedBody> RecordedBodies(const SessionReader& session, const std::string& tracker_name) {
  const std::string tracker = tracker_name.empty() ? OnlyTracker(session.manifest()) : tracker_name;
  const TrackerStreamInfo* info = tracker.empty() ? nullptr : session.manifest().FindTracker(tracker);
  if (!info) throw InputError(session.dir().string(), Str("has no tracker stream '", tracker, "' to replay"));
  std::vector<ndi::RecordedBody> bodies;
  for (const std::string& body : info->bodies) bodies.push_back({body, session.PoseSamples(tracker, body)});
  return bodies;
}

int64_t FirstStampNs(const SessionReader& session) {
  int64_t first = std::numeric_limits<int64_t>::max();
  for (const CameraStreamInfo& camera : session.manifest().cameras)
    if (session.frame_count(camera.name) > 0) first = std::min(first, session.frame(camera.name, 0).record.stamp_ns);
  for (const TrackerStreamInfo& tracker : session.manifest().trackers)
    for (const TrackerRecord& record : session.tracker_records(tracker.name)) first = std::min(first, record.stamp_ns);
  return first == std::numeric_limits<int64_t>::max() ? 0 : first;
}

}  // namespace mocap::capture
