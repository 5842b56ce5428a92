#include "capture/daemon/live_view.h"

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>

#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "core/log.h"

namespace mocap::capture {

namespace {

constexpr size_t kPickedKept = 4;      // frames waiting for their label delay, per camera
constexpr size_t kThumbnailsKept = 8;  // a page asks for the one it was told of, which may be a few steps old

int64_t WallNowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

void LiveViewOptions::check() const {
  if (!(thumbnail_rate_hz >= 0 && thumbnail_rate_hz <= 30))
    throw InputError("live thumbnail rate", Str(thumbnail_rate_hz, " Hz is not in 0..30"));
  if (thumbnail_width_px < 16 || thumbnail_width_px > 4096)
    throw InputError("live thumbnail width", Str(thumbnail_width_px, " px is not in 16..4096"));
  if (jpeg_quality < 1 || jpeg_quality > 100) throw InputError("live jpeg quality", Str(jpeg_quality, " is not in 1..100"));
  if (label_delay_ns < 0 || sample_history_ns <= label_delay_ns)
    throw InputError("live view", "needs 0 <= label_delay_ns < sample_history_ns");
  if (events_kept == 0) throw InputError("live view", "events_kept must be positive");
}

LiveView::LiveView(const LiveViewOptions& options, std::shared_ptr<FrameLabeller> labeller, ManifestFn manifest)
    : options_(options), labeller_(std::move(labeller)), manifest_(std::move(manifest)) {
  options_.check();
  if (options_.thumbnail_rate_hz > 0) thread_ = std::thread([this] { Loop(); });
}

LiveView::~LiveView() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void LiveView::OnFrame(const CapturedFrame& frame) {
  if (!frame.has_color() || options_.thumbnail_rate_hz <= 0) return;
  const int64_t now_ns = MonotonicNowNs();
  const auto period_ns = static_cast<int64_t>(1e9 / options_.thumbnail_rate_hz);
  std::lock_guard lock(mutex_);
  int64_t& last = last_pick_ns_[frame.camera];
  if (last != 0 && now_ns - last < period_ns) return;
  last = now_ns;
  auto& picked = picked_[frame.camera];
  picked.push_back({frame.record, frame.color, frame.color_jpeg, now_ns});  // shares the image; nobody writes into it
  if (picked.size() > kPickedKept) picked.pop_front();
}

void LiveView::OnSample(const CapturedSample& sample) {
  std::lock_guard lock(mutex_);
  auto& samples = samples_[sample.tracker];
  samples.push_back(sample.record);
  while (!samples.empty() && samples.front().stamp_ns < sample.record.stamp_ns - options_.sample_history_ns)
    samples.pop_front();
}

void LiveView::OnEvent(const EventRecord& event) {
  const int64_t age_ms = (MonotonicNowNs() - event.stamp_ns) / 1'000'000;
  std::lock_guard lock(mutex_);
  events_.push_back({{"seq", next_event_seq_++}, {"stamp_ns", event.stamp_ns}, {"wall_ms", WallNowMs() - age_ms},
                     {"kind", event.kind}, {"stream", event.stream}, {"detail", event.detail}});
  if (events_.size() > options_.events_kept) events_.pop_front();
}

nlohmann::json LiveView::Events(size_t max_count) const {
  std::lock_guard lock(mutex_);
  nlohmann::json out = nlohmann::json::array();
  const size_t first = events_.size() > max_count ? events_.size() - max_count : 0;
  for (size_t i = first; i < events_.size(); ++i) out.push_back(events_[i]);
  return out;
}

std::vector<std::shared_ptr<const Thumbnail>> LiveView::Thumbnails() const {
  std::lock_guard lock(mutex_);
  std::vector<std::shared_ptr<const Thumbnail>> out;
  for (const auto& [camera, kept] : thumbnails_) out.push_back(kept.empty() ? nullptr : kept.back());
  return out;
}

std::shared_ptr<const Thumbnail> LiveView::Find(const std::string& camera, int64_t seq) const {
  std::lock_guard lock(mutex_);
  const auto found = thumbnails_.find(camera);
  if (found == thumbnails_.end()) return nullptr;
  for (const auto& t : found->second)
    if (t->seq == seq) return t;
  return nullptr;
}

// The newest picked frame of `camera` that is old enough; older ones are skipped.
std::optional<LiveView::Picked> LiveView::NextDue(const std::string& camera, int64_t now_ns) {
  std::lock_guard lock(mutex_);
  auto& picked = picked_[camera];
  std::optional<Picked> due;
  while (!picked.empty() && now_ns - picked.front().arrived_ns >= options_.label_delay_ns) {
    due = std::move(picked.front());
    picked.pop_front();
  }
  return due;
}

std::map<std::string, std::vector<TrackerRecord>> LiveView::RecentSamples() const {
  std::lock_guard lock(mutex_);
  std::map<std::string, std::vector<TrackerRecord>> out;
  for (const auto& [tracker, samples] : samples_) out[tracker].assign(samples.begin(), samples.end());
  return out;
}

// JPEG colour (a Kinect v2's, recorded as it came) is decoded here, on the view's low-priority thread, a
// few times a second: the recording path never decodes it.
void LiveView::MakeThumbnail(const std::string& camera, const Picked& picked) {
  cv::Mat color = picked.color;
  if (color.empty()) {
    color = cv::imdecode(*picked.color_jpeg, cv::IMREAD_COLOR);
    if (color.empty()) throw InputError(Str("camera ", camera, " frame ", picked.record.frame), "its JPEG colour does not decode");
  }
  std::optional<FrameLabels> labels;
  std::string label_error;
  if (labeller_) {
    try {
      labels = labeller_->Label(manifest_(), camera, picked.record, RecentSamples());
    } catch (const std::exception& e) {
      label_error = e.what();
    }
  }
  std::shared_ptr<Thumbnail> thumbnail;
  try {
    thumbnail = std::make_shared<Thumbnail>(
        EncodeThumbnail(color, labels ? &*labels : nullptr, options_.thumbnail_width_px, options_.jpeg_quality));
  } catch (const InputError& e) {  // labels that do not fit the frame (a rig with other intrinsics)
    if (!labels) throw;
    label_error = e.what();
    thumbnail = std::make_shared<Thumbnail>(
        EncodeThumbnail(color, nullptr, options_.thumbnail_width_px, options_.jpeg_quality));
  }
  thumbnail->camera = camera;
  thumbnail->frame = picked.record.frame;
  thumbnail->stamp_ns = picked.record.stamp_ns;
  thumbnail->label_error = label_error;
  std::lock_guard lock(mutex_);
  if (!label_error.empty() && label_error != last_label_error_)
    Log().warn("capture: live labels of {}: {}", camera, label_error);  // once per new message
  last_label_error_ = label_error;
  auto& kept = thumbnails_[camera];
  thumbnail->seq = kept.empty() ? 1 : kept.back()->seq + 1;
  kept.push_back(std::move(thumbnail));
  if (kept.size() > kThumbnailsKept) kept.pop_front();
}

void LiveView::Loop() {
  // The page is a convenience; the recording is not: on a busy host the thumbnails wait.
  ::setpriority(PRIO_PROCESS, static_cast<id_t>(::gettid()), 10);
  const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / options_.thumbnail_rate_hz / 2));
  std::unique_lock lock(mutex_);
  while (!stop_) {
    wake_.wait_for(lock, period, [this] { return stop_; });
    if (stop_) break;
    std::vector<std::string> cameras;
    for (const auto& [camera, picked] : picked_) cameras.push_back(camera);
    lock.unlock();
    for (const std::string& camera : cameras) {
      try {
        if (auto due = NextDue(camera, MonotonicNowNs())) MakeThumbnail(camera, *due);
      } catch (const std::exception& e) {
        Log().warn("capture: live thumbnail of {}: {}", camera, e.what());
      }
    }
    lock.lock();
  }
  lock.unlock();
  if (labeller_) labeller_->ThreadEnd();
}

}  // namespace mocap::capture
