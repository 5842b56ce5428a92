#pragma once
// The live page's routes on the control server (docs/live-page.md), behind the same access check as
// the API:
//   GET /                      the page (page/index.html; /live.css and /live.js beside it)
//   GET /live/events           Server-Sent Events: one LiveFeed snapshot per message
//   GET /live/snapshot         the latest snapshot, for clients that poll
//   GET /live/thumbnail.jpg?camera=C&seq=N   a camera's thumbnail N (the snapshot names the newest)
//   GET /live/labels.png?camera=C&seq=N      its labels, to lay over it
#include <string>

#include "capture/daemon/daemon.h"
#include "capture/daemon/live_feed.h"

namespace httplib {
class Server;
}

namespace mocap::capture {

/// `max_viewers` event streams at once (each holds a worker while it lasts); more are answered 503.
void AddLiveRoutes(httplib::Server& server, CaptureDaemon& daemon, LiveFeed& feed, int max_viewers);

/// Whether `path` is one of the page's (all GET and HEAD).
bool IsLivePath(const std::string& path);

}  // namespace mocap::capture
