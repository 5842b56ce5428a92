#include "capture/daemon/live_routes.h"

#include <chrono>

#include "capture/daemon/page_assets.h"
#include "core/check.h"
// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace mocap::capture {

namespace {

// A viewer between `events` and the end of its stream; released once however the stream ends (the
// provider and its copies are gone).
class ViewerSlot {
 public:
  explicit ViewerSlot(LiveFeed& feed) : feed_(feed) {}
  ~ViewerSlot() { feed_.RemoveViewer(); }
  ViewerSlot(const ViewerSlot&) = delete;
  ViewerSlot& operator=(const ViewerSlot&) = delete;

 private:
  LiveFeed& feed_;
};

void ReplyJsonError(httplib::Response& res, int status, const std::string& error) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", error}}.dump(), "application/json");
}

// Without a new snapshot for this long the stream sends a comment line, so a viewer that has gone
// away is noticed (the write fails) even while nothing changes.
constexpr auto kIdleComment = std::chrono::seconds(2);

void ServeEvents(LiveFeed& feed, int max_viewers, httplib::Response& res) {
  if (!feed.TryAddViewer(max_viewers)) {
    ReplyJsonError(res, 503, Str("live page: ", max_viewers, " viewers already; poll GET /live/snapshot instead"));
    return;
  }
  auto slot = std::make_shared<ViewerSlot>(feed);
  res.set_header("Cache-Control", "no-store");
  res.set_chunked_content_provider("text/event-stream", [&feed, slot, seen = int64_t{0}](size_t, httplib::DataSink& sink) mutable {
    const std::optional<LiveFeed::Published> next = feed.WaitNewer(seen, kIdleComment);
    if (!next) return false;  // the server stops
    if (next->version == seen || !next->json) return sink.write(": idle\n\n", 9);
    seen = next->version;
    const std::string message = "data: " + *next->json + "\n\n";
    return sink.write(message.data(), message.size());  // false: the viewer is gone or too slow
  });
}

void ServeSnapshot(LiveFeed& feed, httplib::Response& res) {
  const LiveFeed::Published latest = feed.Latest();
  res.set_header("Cache-Control", "no-store");
  res.set_content(latest.json ? *latest.json : std::string("{}"), "application/json");
}

// Thumbnail `seq` of `camera`: its JPEG, or its labels PNG. They never change, so they may be cached.
void ServeThumbnail(const LiveView& live, const httplib::Request& req, httplib::Response& res, bool labels) {
  const std::string camera = req.get_param_value("camera");
  int64_t seq = 0;
  try {
    seq = std::stoll(req.get_param_value("seq"));
  } catch (const std::exception&) {
    return ReplyJsonError(res, 400, Str("GET ", req.path, ": needs ?camera=NAME&seq=N (from /live/snapshot)"));
  }
  const std::shared_ptr<const Thumbnail> t = live.Find(camera, seq);
  if (!t || (labels && t->labels_png.empty()))
    return ReplyJsonError(res, 404, Str("GET ", req.path, ": no ", labels ? "labels" : "thumbnail", " ", seq, " of camera '",
                                        camera, "' (only the last few are kept)"));
  res.set_header("Cache-Control", "private, max-age=60");
  res.set_content(labels ? t->labels_png : t->jpeg, labels ? "image/png" : "image/jpeg");
}

}  // namespace

bool IsLivePath(const std::string& path) {
  for (const PageAsset& asset : PageAssets())
    if (path == asset.path) return true;
  return path == "/live/events" || path == "/live/snapshot" || path == "/live/thumbnail.jpg" || path == "/live/labels.png";
}

void AddLiveRoutes(httplib::Server& server, CaptureDaemon& daemon, LiveFeed& feed, int max_viewers) {
  for (const PageAsset& asset : PageAssets()) {
    server.Get(asset.path, [&asset](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-cache");
      // Everything the page uses comes from the daemon itself.
      res.set_header("Content-Security-Policy", "default-src 'self'; img-src 'self' data:; base-uri 'none'; frame-ancestors 'none'");
      res.set_content(asset.body.data(), asset.body.size(), asset.content_type);
    });
  }
  server.Get("/live/events", [&feed, max_viewers](const httplib::Request&, httplib::Response& res) {
    ServeEvents(feed, max_viewers, res);
  });
  server.Get("/live/snapshot", [&feed](const httplib::Request&, httplib::Response& res) { ServeSnapshot(feed, res); });
  server.Get("/live/thumbnail.jpg", [&daemon](const httplib::Request& req, httplib::Response& res) {
    ServeThumbnail(daemon.live(), req, res, false);
  });
  server.Get("/live/labels.png", [&daemon](const httplib::Request& req, httplib::Response& res) {
    ServeThumbnail(daemon.live(), req, res, true);
  });
}

}  // namespace mocap::capture
