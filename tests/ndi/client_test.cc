// The client against the in-process emulator: over TCP loopback and over a pseudo-terminal (the
// serial path), with reconnects, corrupted bytes and tool-definition uploads.
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <array>
#include <map>
#include <mutex>
#include <thread>

#include "capture/ndi/client.h"
#include "capture/ndi/emulator.h"
#include "capture/ndi/link.h"
#include "capture/ndi/transport.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

using namespace std::chrono_literals;

// Gathers what the client delivers (callbacks run on the client's thread).
class Collector {
 public:
  NdiClient::SampleCallback samples() {
    return [this](const TrackerSample& s) {
      std::lock_guard lock(mutex_);
      samples_.push_back(s);
    };
  }
  NdiClient::EventCallback events() {
    return [this](const TrackerEvent& e) {
      std::lock_guard lock(mutex_);
      events_.push_back(e);
    };
  }
  std::vector<TrackerSample> Samples() {
    std::lock_guard lock(mutex_);
    return samples_;
  }
  std::vector<TrackerEvent> Events(TrackerEventKind kind) {
    std::lock_guard lock(mutex_);
    std::vector<TrackerEvent> out;
    for (const TrackerEvent& e : events_)
      if (e.kind == kind) out.push_back(e);
    return out;
  }
  /// Waits until `predicate` holds or `timeout` passes.
  template <typename Predicate>
  bool WaitFor(Predicate predicate, std::chrono::milliseconds timeout = 3000ms) {
    const auto stop = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < stop) {
      if (predicate()) return true;
      std::this_thread::sleep_for(10ms);
    }
    return predicate();
  }

 private:
  std::mutex mutex_;
  std::vector<TrackerSample> samples_;
  std::vector<TrackerEvent> events_;
};

std::shared_ptr<const TrajectorySource> Circles(int bodies) {
  return std::make_shared<ScriptedTrajectory>(DefaultTrajectoryScript(bodies));
}

// Every delivered pose matches the emulator's ground truth for its frame.
void ExpectMatchesTruth(const std::vector<TrackerSample>& samples, const Emulator& emulator,
                        const TrajectorySource& truth, double tolerance_m, const std::map<int, int>& body_of_handle) {
  for (const TrackerSample& sample : samples) {
    for (const BodySample& body : sample.bodies) {
      if (!body.has_pose) continue;
      const int index = body_of_handle.at(body.handle);
      const Rigid3d expected = truth.At(index, emulator.model().TimeOfFrame(body.frame_number)).T_tracker_body;
      ASSERT_LT(TranslationDistanceM(body.T_tracker_body, expected), tolerance_m) << "frame " << body.frame_number;
      ASSERT_LT(RotationDistanceDeg(body.T_tracker_body, expected), 0.01);
    }
  }
}

TEST(NdiClient, TcpLoopbackDeliversWhatTheEmulatorServes) {
  auto truth = Circles(2);
  Emulator emulator({.port = 0, .tracker = {.rate_hz = 100, .noise_mm = 0.2, .seed = 3}}, truth);
  std::mutex served_mutex;
  std::map<std::pair<uint32_t, int>, std::array<double, 3>> served_mm;  // (frame, handle) -> position
  emulator.SetServedCallback([&](const TrackingReply& reply, bool) {
    std::lock_guard lock(served_mutex);
    for (const HandleReport& h : reply.handles) served_mm[{h.frame_number, h.handle}] = h.t_mm;
  });
  emulator.Start();
  Collector got;
  NdiClient client({.port = emulator.port(), .poll_rate_hz = 100}, got.samples(), got.events());
  client.Open();
  EXPECT_EQ(client.state(), NdiClient::State::kOpen);
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= 40; }));
  client.Close();
  EXPECT_EQ(client.state(), NdiClient::State::kClosed);

  const std::vector<TrackerSample> samples = got.Samples();
  ASSERT_EQ(client.handles().size(), 2u);
  EXPECT_EQ(client.handles()[0].second, "handle-01");
  uint32_t previous = 0;
  int64_t previous_ns = 0;
  for (const TrackerSample& s : samples) {
    ASSERT_EQ(s.bodies.size(), 2u);
    EXPECT_GT(s.bodies[0].frame_number, previous);  // repeats skipped, order kept
    EXPECT_GT(s.host_stamp_ns, previous_ns);
    previous = s.bodies[0].frame_number;
    previous_ns = s.host_stamp_ns;
    for (const BodySample& b : s.bodies) {
      EXPECT_EQ(b.status, PoseStatus::kValid);
      EXPECT_EQ(ToPoseSample(s, b).stamp_ns, s.host_stamp_ns);
      EXPECT_EQ(b.port_status, 0x31u);
      EXPECT_NEAR(b.rms_error_m, (0.1 + 0.5 * 0.2) * 1e-3, 1e-9);
    }
  }
  ExpectMatchesTruth(samples, emulator, *truth, 5 * 0.2e-3 * std::sqrt(3.0), {{1, 0}, {2, 1}});
  // Exactly what was served (noise included), up to float precision.
  std::lock_guard lock(served_mutex);
  for (const TrackerSample& s : samples) {
    for (const BodySample& b : s.bodies) {
      const std::array<double, 3>& sent = served_mm.at({b.frame_number, b.handle});
      for (int axis = 0; axis < 3; ++axis) EXPECT_NEAR(b.T_tracker_body.translation()[axis] * 1e3, sent[axis], 1e-3);
    }
  }
  const NdiClientStats stats = client.stats();
  EXPECT_EQ(stats.crc_errors, 0u);
  EXPECT_EQ(stats.samples, samples.size());
  EXPECT_EQ(got.Events(TrackerEventKind::kConnected).size(), 1u);
}

// With BX the client asks for the tools' 3D markers (0x0809) and reports how many each tool had: all of
// the emulated tool's markers while VALID, none while MISSING; TX has no such option (-1).
TEST(NdiClient, ReportsEachToolsMarkerCountWithBx) {
  auto truth = Circles(2);
  Emulator emulator({.port = 0, .tracker = {.rate_hz = 100, .dropout = 0.3, .seed = 5, .markers_per_tool = 5}}, truth);
  emulator.Start();
  Collector got;
  NdiClient client({.port = emulator.port(), .poll_rate_hz = 100}, got.samples(), got.events());
  client.Open();
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= 40; }));
  client.Close();
  int valid = 0, missing = 0;
  for (const TrackerSample& s : got.Samples())
    for (const BodySample& b : s.bodies) {
      EXPECT_EQ(b.markers, b.ndi_status == HandleStatus::kValid ? 5 : 0) << "frame " << b.frame_number;
      ++(b.ndi_status == HandleStatus::kValid ? valid : missing);
    }
  EXPECT_GT(valid, 0);
  EXPECT_GT(missing, 0) << "30 % dropout";

  Collector tx;
  NdiClient ascii({.port = emulator.port(), .poll_rate_hz = 100, .use_bx = false}, tx.samples(), tx.events());
  ascii.Open();
  ascii.StartStreaming();
  ASSERT_TRUE(tx.WaitFor([&] { return tx.Samples().size() >= 5; }));
  ascii.Close();
  for (const TrackerSample& s : tx.Samples())
    for (const BodySample& b : s.bodies) EXPECT_EQ(b.markers, -1);
}

TEST(NdiClient, TxFallbackAndStatuses) {
  TrajectoryScript script = ParseTrajectoryScript(
      "volume -400 400 -400 400 -2000 -1000 30\nstatic ok 0 0 -1500 0.7071 0 0.7071 0\nstatic edge 380 0 -1500\n"
      "static out 900 0 -1500\nstatic hidden 0 0 -1500\nmissing hidden 0 100\n",
      "script");
  auto truth = std::make_shared<ScriptedTrajectory>(script);
  Emulator emulator({.port = 0, .tracker = {.rate_hz = 50, .volume = script.volume}}, truth);
  emulator.Start();
  Collector got;
  NdiClient client({.port = emulator.port(), .poll_rate_hz = 50, .use_bx = false}, got.samples(), got.events());
  client.Open();
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= 5; }));
  client.Close();
  const TrackerSample s = got.Samples().back();
  ASSERT_EQ(s.bodies.size(), 4u);
  EXPECT_EQ(s.bodies[0].status, PoseStatus::kValid);
  EXPECT_EQ(s.bodies[1].status, PoseStatus::kPartiallyInVolume);
  EXPECT_EQ(s.bodies[2].status, PoseStatus::kOutOfVolume);
  EXPECT_TRUE(s.bodies[2].has_pose);  // reported with 0x0800, flagged
  EXPECT_EQ(s.bodies[3].status, PoseStatus::kMissing);
  EXPECT_FALSE(s.bodies[3].has_pose);
  EXPECT_EQ(s.bodies[3].frame_number, s.bodies[0].frame_number);
  // TX precision: 0.01 mm and 1e-4 in the quaternion.
  ExpectMatchesTruth({s}, emulator, *truth, 2e-5, {{1, 0}, {2, 1}, {3, 2}, {4, 3}});
}

TEST(NdiClient, UploadsRomFilesAndNamesBodies) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("ndi_rom_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* name : {"a.rom", "b.rom"}) std::ofstream(dir / name, std::ios::binary) << std::string(752, '\x5A');
  auto truth = Circles(2);
  Emulator emulator({.port = 0, .tracker = {.preloaded_handles = false}}, truth);
  emulator.Start();
  Collector got;
  NdiClientOptions options{.port = emulator.port()};
  options.tools = {{"wand", (dir / "a.rom").string()}, {"cup", (dir / "b.rom").string(), ToolMode::kStatic}};
  NdiClient client(options, got.samples(), got.events());
  client.Open();
  ASSERT_EQ(client.handles().size(), 2u);
  EXPECT_EQ(client.handles()[0], (std::pair<int, std::string>{0x0A, "wand"}));
  EXPECT_EQ(client.handles()[1], (std::pair<int, std::string>{0x0B, "cup"}));
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return !got.Samples().empty(); }));
  client.Close();
  EXPECT_EQ(got.Samples()[0].bodies[1].name, "cup");
  // 752 bytes = 12 PVWR chunks each; plus INIT, PHSR x3, PHRQ x2, PINIT x2, PENA x2, TSTART, BX..., TSTOP.
  EXPECT_GE(emulator.stats().commands, 2u * 12 + 12);

  options.tools = {{"ghost", (dir / "missing.rom").string()}};
  NdiClient bad(options, nullptr, nullptr);
  EXPECT_THROW(bad.Open(), InputError);
  std::filesystem::remove_all(dir);
}

TEST(NdiClient, RefusalsAndUnreachableTrackerAreClearErrors) {
  Emulator emulator({.port = 0, .tracker = {.preloaded_handles = false}}, Circles(1));
  emulator.Start();
  NdiClientOptions options{.port = emulator.port()};
  options.tools = {{"a", ""}};  // wants a wired handle, the tracker has none
  NdiClient client(options, nullptr, nullptr);
  try {
    client.Open();
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1 tools without a .rom file"), std::string::npos);
  }
  const int port = emulator.port();
  emulator.Stop();
  NdiClient nobody({.port = port, .connect_timeout_ms = 200}, nullptr, nullptr);
  EXPECT_THROW(nobody.Open(), TransportError);
  EXPECT_THROW(NdiClient({.port = 0}, nullptr, nullptr), InputError);
}

TEST(NdiLink, DeviceErrorsNameCommandCodeAndMeaning) {
  Emulator emulator({.port = 0, .latency_ms = 40}, Circles(1));
  emulator.Start();
  Link link(ConnectTcp("127.0.0.1", emulator.port(), 1000));
  EXPECT_EQ(link.Command("INIT:", 1000), "OKAY");
  try {
    link.Bx(0x0801, 1000);
    FAIL() << "BX before TSTART must be refused";
  } catch (const ReplyError& e) {
    EXPECT_EQ(e.kind(), ReplyError::Kind::kDeviceError);
    EXPECT_EQ(e.code(), 0x0C);
    EXPECT_STREQ(e.what(), "BX:0801: tracker replied ERROR0C (Command is invalid while in the current operating mode)");
  }
  EXPECT_EQ(link.counters().device_errors, 1u);
  // The emulator's injected latency delays tracking replies only.
  link.Command("PINIT:01", 1000);
  link.Command("PENA:01D", 1000);
  link.Command("TSTART:", 1000);
  const auto start = std::chrono::steady_clock::now();
  const TrackingReply reply = link.Bx(0x0801, 1000);
  EXPECT_GE(std::chrono::steady_clock::now() - start, 40ms);
  ASSERT_EQ(reply.handles.size(), 1u);
  EXPECT_THROW(link.Bx(0x0801, 10), ReplyError);  // shorter than the latency: a timeout ...
  EXPECT_EQ(link.counters().timeouts, 1u);
  std::this_thread::sleep_for(100ms);
  const TrackingReply fresh = link.Bx(0x0801, 1000);  // ... and the late reply is dropped, not misread
  ASSERT_EQ(fresh.handles.size(), 1u);
  EXPECT_GE(fresh.handles[0].frame_number, reply.handles[0].frame_number + 4);  // 60 Hz, 100 ms later
}

// A tracker that hangs up must reach the client as a TransportError (which it reconnects after), not
// as SIGPIPE ending the process: write to a socket whose peer has closed until the kernel refuses.
TEST(NdiClient, WritingToATrackerThatHungUpIsAnErrorNotASignal) {
  const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(listener, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof(address)), 0);
  ASSERT_EQ(::listen(listener, 1), 0);
  socklen_t length = sizeof(address);
  ASSERT_EQ(::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length), 0);
  auto transport = ConnectTcp("127.0.0.1", ntohs(address.sin_port), 1000);
  const int peer = ::accept(listener, nullptr, nullptr);
  ASSERT_GE(peer, 0);
  ::close(peer);
  ::close(listener);
  bool refused = false;
  for (int i = 0; i < 100 && !refused; ++i) {
    try {
      transport->Write("BX 0801\r");
      std::this_thread::sleep_for(5ms);  // the peer's RST arrives; the next write then fails with EPIPE
    } catch (const TransportError& e) {
      refused = true;
      EXPECT_NE(std::string(e.what()).find("write failed"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(refused);
}

TEST(NdiClient, ReconnectsAfterTheTrackerRestartsAndReportsTheGap) {
  auto truth = Circles(1);
  auto emulator = std::make_unique<Emulator>(EmulatorOptions{.port = 0, .tracker = {.rate_hz = 100}}, truth);
  emulator->Start();
  const int port = emulator->port();
  Collector got;
  NdiClient client({.port = port, .poll_rate_hz = 100, .reconnect_initial_ms = 20, .reconnect_max_ms = 100},
                   got.samples(), got.events());
  client.Open();
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= 10; }));
  emulator->Stop();
  const auto killed = std::chrono::steady_clock::now();
  ASSERT_TRUE(got.WaitFor([&] { return !got.Events(TrackerEventKind::kDisconnected).empty(); }));
  std::this_thread::sleep_for(300ms);
  emulator = std::make_unique<Emulator>(EmulatorOptions{.port = port, .tracker = {.rate_hz = 100, .first_frame = 5000}}, truth);
  emulator->Start();
  ASSERT_TRUE(got.WaitFor([&] { return !got.Events(TrackerEventKind::kGap).empty(); }));
  const size_t after_gap = got.Samples().size();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= after_gap + 10; }));
  client.Close();
  const double down_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  const TrackerEvent gap = got.Events(TrackerEventKind::kGap).at(0);
  EXPECT_GE(gap.gap_ns, 300'000'000);
  EXPECT_LT(gap.gap_ns, static_cast<int64_t>(down_s * 1e9));
  EXPECT_LT(gap.last_frame_before, 5000u);
  EXPECT_GE(gap.first_frame_after, 5000u);
  EXPECT_EQ(client.stats().reconnects, 1u);
  EXPECT_EQ(client.stats().disconnects, 1u);
  EXPECT_EQ(got.Events(TrackerEventKind::kReconnected).size(), 1u);
}

TEST(NdiClient, CorruptedBytesAreCountedAndNeverDelivered) {
  auto truth = Circles(2);
  Emulator emulator({.port = 0, .corrupt = 0.2, .tracker = {.rate_hz = 200, .seed = 11}}, truth);
  emulator.Start();
  Collector got;
  NdiClient client({.port = emulator.port(), .poll_rate_hz = 200, .reply_timeout_ms = 250, .lost_after_failures = 50},
                   got.samples(), got.events());
  client.Open();
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= 150; }, 5000ms));
  client.Close();
  const NdiClientStats stats = client.stats();
  const EmulatorStats served = emulator.stats();
  EXPECT_GT(served.corrupted_replies, 10u);
  EXPECT_GT(stats.crc_errors, 0u);
  // Every corrupted reply is caught (by a CRC, the framing, or a timeout when its CR was hit), none is
  // delivered. Timeouts can also come from a loaded machine, so they only count towards the lower bound.
  EXPECT_LE(stats.crc_errors + stats.malformed_replies, served.corrupted_replies);
  EXPECT_GE(stats.crc_errors + stats.malformed_replies + stats.timeouts + 1, served.corrupted_replies);
  EXPECT_EQ(stats.disconnects, 0u);
  ExpectMatchesTruth(got.Samples(), emulator, *truth, 1e-6, {{1, 0}, {2, 1}});
  EXPECT_FALSE(got.Events(TrackerEventKind::kReplyError).empty());
}

TEST(NdiClient, SerialOverPseudoTerminalWithBaudChange) {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  const std::string slave = ::ptsname(master);
  auto truth = Circles(1);
  Emulator emulator({.tracker = {.rate_hz = 100}}, truth);
  emulator.ServeFd(master);
  Collector got;
  NdiClientOptions options{.transport = NdiClientOptions::TransportKind::kSerial, .serial_device = slave,
                           .serial_baud = 115200, .poll_rate_hz = 100, .serial_probe_timeout_ms = 2000};
  NdiClient client(options, got.samples(), got.events());
  client.Open();
  EXPECT_EQ(emulator.stats().last_baud, 115200);
  client.StartStreaming();
  ASSERT_TRUE(got.WaitFor([&] { return got.Samples().size() >= 20; }));
  client.Close();
  EXPECT_EQ(emulator.stats().last_baud, 9600);  // COMM:00000 before closing
  ExpectMatchesTruth(got.Samples(), emulator, *truth, 1e-6, {{1, 0}});
  emulator.Stop();
  ::close(master);
}

}  // namespace
}  // namespace mocap::ndi
