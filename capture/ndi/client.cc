#include "capture/ndi/client.h"

#include <time.h>

#include <algorithm>
#include <chrono>

#include "capture/ndi/convert.h"
#include "capture/ndi/tool_setup.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

constexpr int kSerialResetMs = 7000;     // BREAK -> RESET may take this long (§1)

void Add(LinkCounters& into, const LinkCounters& from) {
  into.crc_errors += from.crc_errors;
  into.malformed_replies += from.malformed_replies;
  into.timeouts += from.timeouts;
  into.device_errors += from.device_errors;
}

}  // namespace

int64_t MonotonicNowNs() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::string_view ToString(TrackerEventKind kind) {
  switch (kind) {
    case TrackerEventKind::kConnected: return "connected";
    case TrackerEventKind::kDisconnected: return "disconnected";
    case TrackerEventKind::kReconnected: return "reconnected";
    case TrackerEventKind::kGap: return "gap";
    case TrackerEventKind::kReplyError: return "reply_error";
    case TrackerEventKind::kDeviceError: return "device_error";
    case TrackerEventKind::kSystemStatus: return "system_status";
  }
  return "unknown";
}

void NdiClientOptions::check() const {
  if (transport == TransportKind::kTcp && (port <= 0 || port > 65535)) throw InputError("ndi.port", Str(port, " is not a TCP port"));
  if (transport == TransportKind::kTcp && host.empty()) throw InputError("ndi.host", "empty host name");
  if (transport == TransportKind::kSerial && serial_device.empty()) throw InputError("ndi.serial_device", "no serial device given");
  if (transport == TransportKind::kSerial) BaudRateFromBaud(serial_baud);
  if (!(poll_rate_hz > 0 && poll_rate_hz <= 2000)) throw InputError("ndi.poll_rate_hz", Str(poll_rate_hz, " is not in (0, 2000]"));
  if (!(reply_options & reply_option::kTransforms)) throw InputError("ndi.reply_options", "must include 0x0001 (transforms)");
  if (connect_timeout_ms <= 0 || init_timeout_ms <= 0 || reply_timeout_ms <= 0 || serial_probe_timeout_ms <= 0) throw InputError("ndi timeouts", "must be positive");
  if (lost_after_failures < 1) throw InputError("ndi.lost_after_failures", "must be at least 1");
  if (reconnect_initial_ms <= 0 || reconnect_max_ms < reconnect_initial_ms)
    throw InputError("ndi.reconnect", "need 0 < reconnect_initial_ms <= reconnect_max_ms");
  for (const ToolSpec& tool : tools)
    if (tool.name.empty()) throw InputError("ndi.tools", "every tool needs a name");
}

NdiClient::NdiClient(NdiClientOptions options, SampleCallback on_sample, EventCallback on_event)
    : options_(std::move(options)), on_sample_(std::move(on_sample)), on_event_(std::move(on_event)) {
  options_.check();
}

NdiClient::~NdiClient() { Close(); }

void NdiClient::Connect() {
  if (options_.transport == NdiClientOptions::TransportKind::kTcp) {
    link_ = std::make_unique<Link>(ConnectTcp(options_.host, options_.port, options_.connect_timeout_ms));
    link_->Command(InitCommand(), options_.init_timeout_ms);
    return;
  }
  link_ = std::make_unique<Link>(OpenSerial(options_.serial_device, 9600));
  try {
    link_->Command(InitCommand(), options_.serial_probe_timeout_ms);
  } catch (const ReplyError&) {
    // Not answering at 9600 (left at another rate?): a BREAK resets it to 9600 and it answers RESET
    // (§1). Some USB-serial adapters drop the BREAK, so INIT is tried again either way.
    link_->transport().SendBreak();
    const std::optional<AsciiReply> reset = link_->ReadUnsolicited(kSerialResetMs);
    try {
      link_->Command(InitCommand(), options_.init_timeout_ms);
    } catch (const ReplyError& e) {
      throw TransportError(link_->transport().Describe() + ": no reply to INIT at 9600" +
                           (reset ? "" : ", nor RESET after a serial break") + " (" + e.what() + ")");
    }
  }
  if (options_.serial_baud != 9600) {
    link_->Command(CommCommand(BaudRateFromBaud(options_.serial_baud)), options_.reply_timeout_ms);
    link_->transport().SetBaudRate(options_.serial_baud);
  }
}

void NdiClient::Setup() {
  std::vector<EnabledHandle> enabled = SetupTools(*link_, options_.tools, options_.reply_timeout_ms);
  std::lock_guard lock(mutex_);
  handles_.clear();
  for (EnabledHandle& h : enabled) handles_.emplace_back(h.handle, std::move(h.name));
}

void NdiClient::Open() {
  MOCAP_CHECK(state_ == State::kCreated, "NdiClient::Open in state ", static_cast<int>(state_.load()));
  Connect();
  Setup();
  state_ = State::kOpen;
}

void NdiClient::StartStreaming() {
  MOCAP_CHECK(state_ == State::kOpen, "NdiClient::StartStreaming before Open");
  link_->Command(TstartCommand(), options_.init_timeout_ms);
  state_ = State::kStreaming;
  Emit(TrackerEventKind::kConnected, "tracking on " + link_->transport().Describe());
  thread_ = std::thread([this] { PollLoop(); });
}

void NdiClient::Close() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (link_) {
    try {
      if (state_ == State::kStreaming) link_->Command(TstopCommand(), options_.reply_timeout_ms);
      if (link_->transport().is_serial()) link_->Command(CommCommand(BaudRateFromBaud(9600)), options_.reply_timeout_ms);
    } catch (const std::exception&) {
      // Closing anyway: the tracker is gone or will be reset on the next Open.
    }
    DropLink();
    SyncCounters();
  }
  state_ = State::kClosed;
}

NdiClientStats NdiClient::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::vector<std::pair<int, std::string>> NdiClient::handles() const {
  std::lock_guard lock(mutex_);
  return handles_;
}

void NdiClient::SyncCounters() {
  LinkCounters total = folded_;
  if (link_) Add(total, link_->counters());
  std::lock_guard lock(mutex_);
  stats_.crc_errors = total.crc_errors;
  stats_.malformed_replies = total.malformed_replies;
  stats_.timeouts = total.timeouts;
  stats_.device_errors = total.device_errors;
}

void NdiClient::DropLink() {
  if (!link_) return;
  Add(folded_, link_->counters());
  link_.reset();
}

bool NdiClient::SleepFor(int64_t ns) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, std::chrono::nanoseconds(std::max<int64_t>(ns, 0)), [this] { return stop_; });
  return !stop_;
}

void NdiClient::Emit(TrackerEventKind kind, std::string message) {
  if (on_event_) on_event_(TrackerEvent{kind, MonotonicNowNs(), std::move(message)});
}

}  // namespace mocap::ndi
