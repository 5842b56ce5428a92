// The live page's streams against bad clients while a session records (docs/live-page.md): 100 viewers
// on loopback for 10 s (each on the event stream, fetching every new thumbnail and its labels), a viewer
// that never reads, one that asks for images and never reads them, and clients that hang up mid-stream
// over and over. The recording must not notice: no drop, every frame the camera made written, and the
// API answering as fast as ever. About 12 s: label slow.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <arpa/inet.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "capture/daemon/control_server.h"
#include "capture/daemon/sources.h"
#include "test_dirs.h"
// Last: it pulls in <resolv.h>, whose `_res` macro breaks Eigen headers included after it.
#include <httplib.h>

namespace mocap::capture {
namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr int kViewers = 100;
constexpr auto kDuration = 10s;

class SquareLabeller final : public FrameLabeller {
 public:
  std::optional<FrameLabels> Label(const SessionManifest&, const std::string&, const CameraFrameRecord& frame,
                                   const std::map<std::string, std::vector<TrackerRecord>>&) override {
    FrameLabels labels;
    labels.instance_ids = cv::Mat(480, 640, CV_16UC1, cv::Scalar(0));
    labels.instance_ids(cv::Rect(static_cast<int>(frame.frame % 500), 100, 100, 100)).setTo(1);
    labels.instances = {{1, "square", "b", true, ""}};
    return labels;
  }
};

// A raw loopback connection with a tiny receive buffer, for clients that misbehave.
int Connect(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  const int small = 1024;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &small, sizeof small);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) ADD_FAILURE() << "connect failed";
  return fd;
}

void Send(int fd, const std::string& text) { (void)::send(fd, text.data(), text.size(), MSG_NOSIGNAL); }

struct ViewerTally {
  int messages = 0, images = 0, image_failures = 0;
};

// One viewer: the event stream, and the newest thumbnail and its labels fetched as the page does.
void View(int port, const std::atomic<bool>& stop, ViewerTally& tally) {
  httplib::Client stream("127.0.0.1", port);
  httplib::Client images("127.0.0.1", port);
  std::string buffer;
  int64_t seq_seen = 0;
  stream.Get("/live/events", [&](const char* data, size_t size) {
    buffer.append(data, size);
    nlohmann::json newest;
    for (size_t end; (end = buffer.find("\n\n")) != std::string::npos; buffer.erase(0, end + 2)) {
      if (buffer.rfind("data: ", 0) != 0) continue;
      ++tally.messages;
      newest = nlohmann::json::parse(buffer.substr(6, end - 6));
    }
    for (const auto& t : newest.is_object() ? newest["thumbnails"] : nlohmann::json::array()) {
      if (t["seq"].get<int64_t>() <= seq_seen) continue;
      seq_seen = t["seq"];
      const std::string query = "?camera=cam&seq=" + std::to_string(seq_seen);
      for (const char* path : {"/live/thumbnail.jpg", "/live/labels.png"}) {
        const auto r = images.Get(std::string(path) + query);
        r && r->status == 200 ? ++tally.images : ++tally.image_failures;
      }
    }
    return !stop;
  });
}

TEST(LivePageClients, HundredViewersSlowReadersAndHangupsDoNotDisturbTheRecording) {
  std::vector<std::unique_ptr<CaptureSource>> sources;
  sources.push_back(CreateSimulatedCamera({.stream = "cam", .rate_hz = 30}));
  sources.push_back(CreateSimulatedTracker({.stream = "trk", .bodies = 4, .rate_hz = 120}));
  CaptureDaemonOptions options{.sessions_dir = testing::FreshCaptureDir("live_clients")};
  options.live = {.thumbnail_rate_hz = 4, .label_delay_ns = 100'000'000};
  options.labeller = std::make_shared<SquareLabeller>();
  CaptureDaemon daemon(options, std::move(sources));
  ControlServer server(daemon, {.port = 0});
  const int port = server.port();
  httplib::Client api("127.0.0.1", port);
  ASSERT_EQ(api.Post("/start", R"({"name": "watched"})", "application/json")->status, 200);

  std::atomic<bool> stop{false};
  std::vector<ViewerTally> tallies(kViewers);
  std::vector<std::thread> threads;
  for (int i = 0; i < kViewers; ++i) threads.emplace_back(View, port, std::cref(stop), std::ref(tallies[static_cast<size_t>(i)]));
  // Never reads: neither its event stream nor 200 image answers.
  const int slow_stream = Connect(port);
  Send(slow_stream, "GET /live/events HTTP/1.1\r\nHost: x\r\n\r\n");
  const int slow_images = Connect(port);
  std::string requests;
  for (int i = 0; i < 200; ++i) requests += "GET /live.js HTTP/1.1\r\nHost: x\r\n\r\n";
  Send(slow_images, requests);
  // Hangs up mid-stream, over and over.
  std::atomic<int> hangups{0};
  threads.emplace_back([&] {
    while (!stop) {
      const int fd = Connect(port);
      Send(fd, "GET /live/events HTTP/1.1\r\nHost: x\r\n\r\n");
      char some[64];
      (void)::recv(fd, some, sizeof some, 0);
      ::close(fd);
      ++hangups;
      std::this_thread::sleep_for(50ms);
    }
  });
  // The API meanwhile.
  double worst_status_s = 0;
  for (const auto end = Clock::now() + kDuration; Clock::now() < end; std::this_thread::sleep_for(200ms)) {
    const auto t0 = Clock::now();
    const auto r = api.Get("/status");
    worst_status_s = std::max(worst_status_s, std::chrono::duration<double>(Clock::now() - t0).count());
    ASSERT_TRUE(r && r->status == 200);
  }
  const auto t0 = Clock::now();
  const nlohmann::json summary = nlohmann::json::parse(api.Post("/stop", "{}", "application/json")->body);
  const double stop_s = std::chrono::duration<double>(Clock::now() - t0).count();
  stop = true;
  for (std::thread& t : threads) t.join();
  ::close(slow_stream);
  ::close(slow_images);

  std::vector<int> messages;
  int images = 0, image_failures = 0;
  for (const ViewerTally& t : tallies) messages.push_back(t.messages), images += t.images, image_failures += t.image_failures;
  std::sort(messages.begin(), messages.end());
  const nlohmann::json& cam = summary["streams"]["cam"];
  const nlohmann::json& trk = summary["streams"]["trk"];
  std::cout << kViewers << " viewers for 10 s: snapshots per viewer min " << messages.front() << " median "
            << messages[messages.size() / 2] << "; " << images << " images fetched (" << image_failures << " gone); "
            << hangups << " hang-ups; /status at most " << worst_status_s << " s, /stop " << stop_s
            << " s; camera " << cam.dump() << ", tracker " << trk.dump() << "\n";
  EXPECT_TRUE(summary["complete"]);
  EXPECT_EQ(cam["dropped"], 0);
  EXPECT_EQ(trk["dropped"], 0);
  EXPECT_EQ(cam["written"], cam["received"]);
  EXPECT_GE(cam["written"].get<int64_t>(), 25 * 10);  // the camera kept its 30 Hz
  // The viewers' side: every viewer kept getting snapshots (2 a second) and images, and the API kept
  // answering. A connection the listen backlog had no room for waits for the kernel's handshake retry
  // (1 s, then 2 s, ...): the slowest viewer then fell far behind the median, some got none before
  // their read timeout, and /status took 1 s.
  EXPECT_GE(messages.front(), std::max(5, messages[messages.size() / 2] / 2));
  EXPECT_GE(images, kViewers * 2);
  EXPECT_LT(worst_status_s, 0.5);
  EXPECT_GE(hangups, 20);
}

}  // namespace
}  // namespace mocap::capture
