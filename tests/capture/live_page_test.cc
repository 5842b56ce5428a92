// The live page's server side (docs/live-page.md): the page and its data served under the API's access
// rules, the token as a cookie for browsers, other sites' pages refused, thumbnails and their labels.
#include <gtest/gtest.h>

#include <chrono>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "capture/daemon/control_server.h"
#include "capture/daemon/sources.h"
#include "core/check.h"
#include "test_dirs.h"
// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace mocap::capture {
namespace {

using namespace std::chrono_literals;

// Labels a 20x10 box at the top left as instance 1, and says instance 2 has no pose.
class BoxLabeller final : public FrameLabeller {
 public:
  std::optional<FrameLabels> Label(const SessionManifest&, const std::string&, const CameraFrameRecord&,
                                   const std::map<std::string, std::vector<TrackerRecord>>& samples) override {
    FrameLabels labels;
    labels.instance_ids = cv::Mat(480, 640, CV_16UC1, cv::Scalar(0));
    labels.instance_ids(cv::Rect(0, 0, 20, 10)).setTo(1);
    labels.instances = {{1, "box", "b1", true, ""}, {2, "ball", "b2", false, "missing_body"}};
    saw_samples = !samples.empty();
    return labels;
  }
  bool saw_samples = false;
};

struct LiveFixture {
  explicit LiveFixture(const std::string& name, const ControlServerOptions& control = {.port = 0}) {
    std::vector<std::unique_ptr<CaptureSource>> sources;
    sources.push_back(CreateSimulatedCamera({.stream = "cam", .rate_hz = 30}));
    sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = 2, .rate_hz = 100}));
    labeller = std::make_shared<BoxLabeller>();
    CaptureDaemonOptions options{.sessions_dir = testing::FreshCaptureDir(name)};
    options.live = {.thumbnail_rate_hz = 5, .label_delay_ns = 50'000'000};
    options.labeller = labeller;
    daemon = std::make_unique<CaptureDaemon>(options, std::move(sources));
    server = std::make_unique<ControlServer>(*daemon, control);
  }
  nlohmann::json Snapshot(httplib::Headers headers = {}) {
    httplib::Client client("127.0.0.1", server->port());
    const auto r = client.Get("/live/snapshot", headers);
    return r && r->status == 200 ? nlohmann::json::parse(r->body) : nlohmann::json();
  }
  std::shared_ptr<BoxLabeller> labeller;
  std::unique_ptr<CaptureDaemon> daemon;
  std::unique_ptr<ControlServer> server;
};

template <typename Fn>
bool WaitFor(Fn fn, std::chrono::milliseconds timeout = 5s) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!fn()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

TEST(LivePage, ServesThePageItsScriptAndStyle) {
  LiveFixture f("live_page_files");
  httplib::Client client("127.0.0.1", f.server->port());
  auto r = client.Get("/");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/html; charset=utf-8");
  EXPECT_NE(r->body.find("<script src=\"/live.js\">"), std::string::npos);
  EXPECT_NE(r->get_header_value("Content-Security-Policy").find("default-src 'self'"), std::string::npos);
  for (const char* path : {"/live.js", "/live.css"}) {
    r = client.Get(path);
    EXPECT_EQ(r->status, 200) << path;
    EXPECT_GT(r->body.size(), 500u) << path;
  }
  EXPECT_EQ(client.Post("/", "", "text/plain")->status, 405);
  EXPECT_EQ(client.Get("/live/nothing")->status, 404);
}

TEST(LivePage, SnapshotHasStatusEventsAndALabelledThumbnail) {
  LiveFixture f("live_page_snapshot");
  httplib::Client client("127.0.0.1", f.server->port());
  ASSERT_EQ(client.Post("/start", R"({"name": "s"})", "application/json")->status, 200);
  nlohmann::json snapshot;
  ASSERT_TRUE(WaitFor([&] {
    snapshot = f.Snapshot();
    return snapshot.contains("thumbnails") && !snapshot["thumbnails"].empty() && !snapshot["events"].empty();
  }));
  EXPECT_EQ(snapshot["status"]["state"], "recording");
  ASSERT_FALSE(snapshot["events"].empty()) << snapshot.dump();  // front() of an empty array is undefined
  EXPECT_EQ(snapshot["events"].front()["detail"], "recording session s");
  const nlohmann::json& t = snapshot["thumbnails"][0];
  EXPECT_EQ(t["camera"], "cam");
  EXPECT_EQ(t["width"], 320);
  EXPECT_EQ(t["height"], 240);
  EXPECT_TRUE(t["labels"]);
  ASSERT_EQ(t["legend"].size(), 2u);
  EXPECT_EQ(t["legend"][1]["reason"], "missing_body");
  EXPECT_TRUE(f.labeller->saw_samples);

  const std::string query = "?camera=cam&seq=" + std::to_string(t["seq"].get<int64_t>());
  auto r = client.Get("/live/thumbnail.jpg" + query);
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(r->get_header_value("Content-Type"), "image/jpeg");
  r = client.Get("/live/labels.png" + query);
  ASSERT_EQ(r->status, 200);
  const cv::Mat png = cv::imdecode(std::vector<uint8_t>(r->body.begin(), r->body.end()), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(png.type(), CV_8UC4);
  ASSERT_EQ(png.size(), cv::Size(320, 240));
  // The 20x10 box at half size: 10x5 pixels of instance 1's colour, its edge opaque; nothing elsewhere.
  cv::Mat alpha;
  cv::extractChannel(png, alpha, 3);
  EXPECT_EQ(cv::countNonZero(alpha), 50);
  EXPECT_EQ(alpha.at<uint8_t>(0, 0), 255);
  EXPECT_LT(alpha.at<uint8_t>(2, 4), 255);
  EXPECT_EQ(InstanceColor(1), t["legend"][0]["color"]);
  EXPECT_EQ(client.Get("/live/labels.png?camera=cam&seq=999999")->status, 404);
  EXPECT_EQ(client.Get("/live/labels.png?camera=cam")->status, 400);
}

TEST(LivePage, BrowsersGetTheTokenAsACookieAndOtherSitesAreRefused) {
  LiveFixture f("live_page_token", {.port = 0, .token = "s3cret"});
  httplib::Client client("127.0.0.1", f.server->port());
  EXPECT_EQ(client.Get("/")->status, 401);
  EXPECT_EQ(client.Get("/?token=wrong")->status, 401);
  const auto page = client.Get("/?token=s3cret");
  ASSERT_EQ(page->status, 200);
  const std::string cookie = page->get_header_value("Set-Cookie");
  EXPECT_EQ(cookie, "mocaplabel_token=s3cret; Path=/; HttpOnly; SameSite=Strict");
  EXPECT_EQ(client.Get("/live/snapshot")->status, 401);
  EXPECT_EQ(client.Get("/live/snapshot?token=s3cret")->status, 401);  // the query only opens the page
  EXPECT_EQ(client.Get("/live/snapshot", {{"Cookie", "a=b; mocaplabel_token=s3cret"}})->status, 200);
  EXPECT_EQ(client.Get("/status", {{"Cookie", "mocaplabel_token=nope"}})->status, 401);

  const httplib::Headers evil = {{"Authorization", "Bearer s3cret"}, {"Origin", "http://evil.example"}};
  const auto refused = client.Post("/start", evil, R"({"name": "x"})", "application/json");
  EXPECT_EQ(refused->status, 403);
  EXPECT_NE(refused->body.find("evil.example"), std::string::npos);
  const std::string own = "http://127.0.0.1:" + std::to_string(f.server->port());
  const httplib::Headers same = {{"Authorization", "Bearer s3cret"}, {"Origin", own}};
  EXPECT_EQ(client.Post("/start", same, R"({"name": "x"})", "application/json")->status, 200);
}

TEST(LivePage, EventStreamSendsSnapshotsAndViewersAreCapped) {
  LiveFixture f("live_page_sse", {.port = 0, .max_live_viewers = 1});
  httplib::Client first("127.0.0.1", f.server->port());
  std::atomic<int> messages{0};
  std::thread viewer([&] {
    std::string received;
    first.Get("/live/events", [&](const char* data, size_t size) {
      received.append(data, size);
      int n = 0;
      for (size_t at = received.find("data: {"); at != std::string::npos; at = received.find("data: {", at + 1)) ++n;
      messages = n;
      return n < 2;  // then hang up
    });
  });
  ASSERT_TRUE(WaitFor([&] { return messages >= 1; }));
  httplib::Client second("127.0.0.1", f.server->port());
  const auto busy = second.Get("/live/events");
  ASSERT_TRUE(busy);
  EXPECT_EQ(busy->status, 503);
  viewer.join();
  EXPECT_GE(messages, 2);
  // The first viewer left: its slot is free again.
  EXPECT_TRUE(WaitFor([&] { return f.Snapshot().value("viewers", -1) == 0; }));
}

TEST(LiveView, KeepsTheNewestEvents) {
  LiveView view({.thumbnail_rate_hz = 0, .events_kept = 3}, nullptr, [] { return SessionManifest{}; });
  for (int i = 0; i < 5; ++i) view.OnEvent({MonotonicNowNs(), "gap", "trk", std::to_string(i)});
  const nlohmann::json events = view.Events(10);
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0]["detail"], "2");
  EXPECT_EQ(events[2]["seq"], 5);
  EXPECT_EQ(view.Events(1).size(), 1u);
  EXPECT_THROW((LiveViewOptions{.thumbnail_rate_hz = 100}.check()), InputError);
  EXPECT_THROW((LiveViewOptions{.label_delay_ns = 5'000'000'000}.check()), InputError);
}

}  // namespace
}  // namespace mocap::capture
