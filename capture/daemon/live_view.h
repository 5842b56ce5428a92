#pragma once
// What the daemon's live page shows beyond `status` (docs/live-page.md): the session's events as they
// happen, and per camera a thumbnail of the latest colour frame with its labels, a few times a second.
//
// The daemon hands the live view a copy of everything its sources push (a colour image is shared, not
// copied). The view keeps the last few seconds of tracker samples and, per camera, a few frames picked
// at the thumbnail rate; its own thread labels a picked frame once it is `label_delay_ns` old (by then
// the tracker samples after the frame's time have arrived, so the poses are interpolated, as the
// labeller does) and encodes the thumbnail once, for every viewer. The labels come from a
// FrameLabeller given by the layer above (the CLI renders them with the labeller's chain and renderer;
// capture knows nothing of labelling). Nothing here can block a device thread for more than a copy
// under a short lock, and the view's thread runs at a lower priority than the recording.
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "capture/daemon/source.h"

namespace mocap::capture {

struct LiveViewOptions {
  double thumbnail_rate_hz = 3;  ///< thumbnails per second per camera; 0: none
  int thumbnail_width_px = 320;  ///< height follows the frame's aspect
  int jpeg_quality = 80;
  /// A picked frame is labelled this long after it arrived: the tracker's samples after the frame's time
  /// (plus the rig's latency) have come in by then, so its poses are interpolated rather than guessed.
  int64_t label_delay_ns = 200'000'000;
  int64_t sample_history_ns = 3'000'000'000;  ///< tracker samples kept per tracker
  size_t events_kept = 200;                   ///< the newest events the page can show
  void check() const;
};

/// The labels of one frame, as the labeller gives them: instance ids per pixel and who is who.
struct FrameLabels {
  cv::Mat instance_ids;  ///< CV_16UC1 at the colour image's size; 0 = background
  struct Instance {
    uint16_t id = 0;
    std::string object, body;
    bool drawn = false;  ///< it had a pose (it may still be outside the image)
    std::string reason;  ///< why not, or the flags of a doubtful pose
  };
  std::vector<Instance> instances;
};

/// Labels live frames. Called on the live view's thread only; ThreadEnd() on that thread before it ends
/// (to release a GL context where it was made current).
class FrameLabeller {
 public:
  virtual ~FrameLabeller() = default;
  /// `samples`: per tracker stream, its recent records in arrival order. Throws on a broken set-up (the
  /// page shows the message); nullopt when this camera has nothing to label.
  virtual std::optional<FrameLabels> Label(const SessionManifest& manifest, const std::string& camera,
                                           const CameraFrameRecord& frame,
                                           const std::map<std::string, std::vector<TrackerRecord>>& samples) = 0;
  virtual void ThreadEnd() {}
};

/// One camera's thumbnail: encoded once, served to every viewer.
struct Thumbnail {
  std::string camera;
  int64_t seq = 0;  ///< per camera, from 1
  int64_t frame = 0, stamp_ns = 0;  ///< the camera record it shows
  int width = 0, height = 0;
  std::string jpeg;        ///< the colour image, downscaled
  std::string labels_png;  ///< RGBA: each instance's colour (see legend) over transparency; "" without labels
  nlohmann::json legend = nlohmann::json::array();  ///< [{id, object, body, color "#rrggbb", drawn, reason}]
  std::string label_error;  ///< why there are no labels ("" when there are, or no labeller)
};

class LiveView {
 public:
  using ManifestFn = std::function<SessionManifest()>;
  /// `labeller` may be null (thumbnails without labels). `manifest` gives the cameras' and trackers'
  /// stream entries (called on the view's thread).
  LiveView(const LiveViewOptions& options, std::shared_ptr<FrameLabeller> labeller, ManifestFn manifest);
  ~LiveView();  ///< stops the thread
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  // From the daemon, on device threads: copies only.
  void OnFrame(const CapturedFrame& frame);
  void OnSample(const CapturedSample& sample);
  void OnEvent(const EventRecord& event);

  /// The newest events, oldest first: [{seq, stamp_ns, wall_ms, kind, stream, detail}].
  nlohmann::json Events(size_t max_count) const;
  /// The newest thumbnail of every camera (null where none yet).
  std::vector<std::shared_ptr<const Thumbnail>> Thumbnails() const;
  /// Thumbnail `seq` of `camera` if it is still kept (the last few are), else null.
  std::shared_ptr<const Thumbnail> Find(const std::string& camera, int64_t seq) const;
  const LiveViewOptions& options() const { return options_; }

 private:
  struct Picked {
    CameraFrameRecord record;
    cv::Mat color;  ///< or, for colour that came as JPEG, empty and decoded on the view's thread:
    std::shared_ptr<const std::vector<uint8_t>> color_jpeg;
    int64_t arrived_ns = 0;
  };
  void Loop();
  std::optional<Picked> NextDue(const std::string& camera, int64_t now_ns);
  void MakeThumbnail(const std::string& camera, const Picked& picked);
  std::map<std::string, std::vector<TrackerRecord>> RecentSamples() const;

  LiveViewOptions options_;
  std::shared_ptr<FrameLabeller> labeller_;
  ManifestFn manifest_;
  mutable std::mutex mutex_;  // guards everything below
  std::map<std::string, std::deque<Picked>> picked_;
  std::map<std::string, int64_t> last_pick_ns_;
  std::map<std::string, std::deque<TrackerRecord>> samples_;
  std::deque<nlohmann::json> events_;
  int64_t next_event_seq_ = 1;
  std::map<std::string, std::deque<std::shared_ptr<const Thumbnail>>> thumbnails_;
  std::string last_label_error_;
  bool stop_ = false;
  std::condition_variable wake_;
  std::thread thread_;
};

/// The colour of instance `id` in the labels PNG (distinct hues), as "#rrggbb".
std::string InstanceColor(uint16_t id);

/// The thumbnail of one frame: colour downscaled to `width_px` (JPEG) and, with labels, their PNG
/// (nearest-neighbour downscaled instance ids, each instance's colour, filled half transparent with an
/// opaque outline). Throws InputError for an image it cannot encode.
Thumbnail EncodeThumbnail(const cv::Mat& color_bgr, const FrameLabels* labels, int width_px, int jpeg_quality);

}  // namespace mocap::capture
