#include "capture/ndi/emulated_tracker.h"

#include <cmath>
#include <cstdio>
#include <random>

#include "capture/ndi/commands.h"
#include "capture/ndi/crc.h"
#include "capture/ndi/cursor.h"
#include "capture/ndi/encode.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

// Error codes the emulator answers with (reply.cc has their texts).
constexpr int kInvalidCommand = 0x01, kBadCommandCrc = 0x04, kParameterCount = 0x07, kInvalidHandle = 0x08,
              kInvalidMode = 0x09, kBadOperatingMode = 0x0C, kNoTool = 0x0D, kHandleNotInitialised = 0x0E,
              kSystemNotInitialised = 0x10, kPinitFailed = 0x13, kOutOfRange = 0x23;

constexpr uint32_t kHealthyPort = port_status::kToolInPort | port_status::kInitialised | port_status::kEnabled;

std::string Hex(unsigned value, int digits) {
  char text[16];
  std::snprintf(text, sizeof(text), "%0*X", digits, value);
  return text;
}

std::optional<int> HandleParam(std::string_view params, size_t extra = 0) {
  if (params.size() != 2 + extra) return std::nullopt;
  TextCursor cursor(params);
  const std::optional<uint32_t> handle = cursor.Hex(2);
  return handle ? std::optional<int>(static_cast<int>(*handle)) : std::nullopt;
}

// A generator seeded by (seed, body, frame), so every poll of one frame reports the same values.
std::mt19937_64 FrameRng(uint64_t seed, int body, uint32_t frame) {
  uint64_t x = seed ^ (static_cast<uint64_t>(body) << 40) ^ frame;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;  // splitmix64 finaliser
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return std::mt19937_64(x ^ (x >> 31));
}

}  // namespace

void EmulatedTrackerOptions::check() const {
  if (!(rate_hz > 0 && rate_hz <= 1000)) throw InputError("emulator rate", Str(rate_hz, " Hz is not in (0, 1000]"));
  if (!(noise_mm >= 0 && noise_mm < 1000)) throw InputError("emulator noise", Str(noise_mm, " mm is not in [0, 1000)"));
  if (!(dropout >= 0 && dropout <= 1)) throw InputError("emulator dropout", Str(dropout, " is not a probability"));
  if (markers_per_tool < 3 || markers_per_tool > 20)
    throw InputError("emulator markers per tool", Str(markers_per_tool, " is not in 3..20 (a tool needs 3 to be fitted)"));
}

void TrackingClock::Start(double t_s) {
  std::lock_guard lock(mutex_);
  if (!start_s_) start_s_ = t_s;
}

void TrackingClock::Stop() {
  std::lock_guard lock(mutex_);
  start_s_.reset();
}

double TrackingClock::Since(double t_s) const {
  std::lock_guard lock(mutex_);
  return start_s_ ? std::max(t_s - *start_s_, 0.0) : 0.0;
}

EmulatedTracker::EmulatedTracker(EmulatedTrackerOptions options, std::shared_ptr<const TrajectorySource> trajectory,
                                 std::shared_ptr<TrackingClock> clock)
    : options_(std::move(options)), trajectory_(std::move(trajectory)),
      clock_(clock ? std::move(clock) : std::make_shared<TrackingClock>()) {
  options_.check();
  MOCAP_CHECK(trajectory_ && trajectory_->body_count() > 0 && trajectory_->body_count() < 0xFF, "trajectory");
}

uint32_t EmulatedTracker::FrameAt(double t_s) const {
  return options_.first_frame + static_cast<uint32_t>(std::floor(std::max(t_s, 0.0) * options_.rate_hz));
}

double EmulatedTracker::TimeOfFrame(uint32_t frame) const {
  return static_cast<double>(frame - options_.first_frame) / options_.rate_hz;
}

double EmulatedTracker::TrackingTime(double t_s) const {
  return options_.clock_from_tstart ? clock_->Since(t_s) : t_s;
}

void EmulatedTracker::Reset() {
  handles_.clear();
  tracking_ = false;
  if (!options_.preloaded_handles) return;
  for (int body = 0; body < trajectory_->body_count(); ++body) handles_[body + 1] = PortHandle{body};
}

EmulatorReply EmulatedTracker::Handle(std::string_view line, double t_s) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  EmulatorReply reply;
  const size_t separator = line.find_first_of(": ");
  if (separator == std::string_view::npos || separator == 0) {
    reply.bytes = FrameErrorReply(kInvalidCommand);
    return reply;
  }
  std::string_view params = line.substr(separator + 1);
  if (line[separator] == ':') {
    // NAME ':' params CRC: the CRC covers everything before it (§2).
    if (params.size() < 4 || Crc16Hex(line.substr(0, line.size() - 4)) != line.substr(line.size() - 4)) {
      reply.bytes = FrameErrorReply(kBadCommandCrc);
      return reply;
    }
    params.remove_suffix(4);
  }
  reply.bytes = Dispatch(line.substr(0, separator), params, t_s, reply);
  return reply;
}

std::string EmulatedTracker::Dispatch(std::string_view name, Params params, double t_s, EmulatorReply& reply) {
  if (name == "INIT") {
    Reset();
    initialised_ = true;
    return FrameReply("OKAY");
  }
  if (name == "APIREV") return FrameReply("G.001.004");
  if (name == "VER") return FrameReply("mocaplabel NDI emulator\nCombined API subset: BX TX PHSR PHRQ PVWR PINIT PENA");
  if (name == "BEEP") return params.size() == 1 && params[0] >= '1' && params[0] <= '9' ? FrameReply("1") : FrameErrorReply(kOutOfRange);
  if (name == "COMM") {
    if (params.size() != 5) return FrameErrorReply(kParameterCount);
    try {
      reply.new_baud = BaudRateFromCode(params[0]).baud;
    } catch (const InputError&) {
      return FrameErrorReply(kOutOfRange);
    }
    return FrameReply("OKAY");
  }
  if (!initialised_) return FrameErrorReply(kSystemNotInitialised);
  if (name == "PHSR") return Phsr(params);
  if (name == "PHRQ") return Phrq(params);
  if (name == "PVWR") return Pvwr(params);
  if (name == "PHF" || name == "PINIT" || name == "PENA" || name == "PDIS") return HandleCommand(name, params);
  if (name == "TSTART") {
    tracking_ = true;
    clock_->Start(t_s);
    return FrameReply("OKAY");
  }
  if (name == "TSTOP") {
    tracking_ = false;
    clock_->Stop();
    return FrameReply("OKAY");
  }
  if (name == "BX" || name == "TX") return Tracking(name, params, t_s, reply);
  return FrameErrorReply(kInvalidCommand);
}

std::string EmulatedTracker::Phsr(Params params) {
  const std::optional<int> query = HandleParam(params);
  if (!query || *query > 4) return FrameErrorReply(kOutOfRange);
  std::string listed;
  int count = 0;
  for (const auto& [number, handle] : handles_) {
    const bool match = *query == 0 || (*query == 2 && !handle.initialised) ||
                       (*query == 3 && handle.initialised && !handle.enabled) || (*query == 4 && handle.enabled);
    if (!match) continue;  // query 1 (to be freed): the emulator never has stale handles
    ++count;
    const unsigned status = (handle.body >= 0 ? 0x001u : 0u) | (handle.initialised ? 0x010u : 0u) | (handle.enabled ? 0x020u : 0u);
    listed += Hex(static_cast<unsigned>(number), 2) + Hex(status, 3);
  }
  return FrameReply(Hex(static_cast<unsigned>(count), 2) + listed);
}

std::string EmulatedTracker::Phrq(Params params) {
  if (params.size() != 14) return FrameErrorReply(kParameterCount);
  // The next body without an initialised handle takes a fresh handle number.
  for (int body = 0; body < trajectory_->body_count(); ++body) {
    bool taken = false;
    for (auto it = handles_.begin(); it != handles_.end();) {
      if (it->second.body == body && !it->second.initialised && !it->second.from_phrq) {
        it = handles_.erase(it);  // a preloaded handle gives way to the requested one
        continue;
      }
      taken |= it->second.body == body;
      ++it;
    }
    if (taken) continue;
    int number = 0x0A;
    while (handles_.count(number)) ++number;
    handles_[number] = PortHandle{body, true};
    return FrameReply(Hex(static_cast<unsigned>(number), 2));
  }
  return FrameErrorReply(kNoTool);
}

std::string EmulatedTracker::Pvwr(Params params) {
  if (params.size() != 2 + 4 + 128) return FrameErrorReply(kParameterCount);
  TextCursor cursor(params);
  const std::optional<uint32_t> number = cursor.Hex(2);
  const std::optional<uint32_t> address = number ? cursor.Hex(4) : std::nullopt;
  if (!address) return FrameErrorReply(kParameterCount);
  for (int i = 0; i < 64; ++i)
    if (!cursor.Hex(2)) return FrameErrorReply(kParameterCount);
  const auto it = handles_.find(static_cast<int>(*number));
  if (it == handles_.end()) return FrameErrorReply(kInvalidHandle);
  if (*address % 64 != 0) return FrameErrorReply(kOutOfRange);
  it->second.rom_written = true;
  return FrameReply("OKAY");
}

std::string EmulatedTracker::HandleCommand(std::string_view name, Params params) {
  const bool pena = name == "PENA";
  const std::optional<int> number = HandleParam(params, pena ? 1 : 0);
  if (!number) return FrameErrorReply(kParameterCount);
  const auto it = handles_.find(*number);
  if (it == handles_.end()) return FrameErrorReply(kInvalidHandle);
  PortHandle& handle = it->second;
  if (name == "PHF") {
    handles_.erase(it);
  } else if (name == "PINIT") {
    if (handle.from_phrq && !handle.rom_written) return FrameErrorReply(kPinitFailed);
    handle.initialised = true;
  } else if (name == "PDIS") {
    handle.enabled = false;
  } else {
    const char mode = params.back();
    if (mode != 'S' && mode != 'D' && mode != 'B') return FrameErrorReply(kInvalidMode);
    if (!handle.initialised) return FrameErrorReply(kHandleNotInitialised);
    handle.enabled = true;
  }
  return FrameReply("OKAY");
}

std::string EmulatedTracker::Tracking(std::string_view name, Params params, double t_s, EmulatorReply& reply) {
  if (!tracking_) return FrameErrorReply(kBadOperatingMode);
  TextCursor cursor(params);
  const std::optional<uint32_t> options = cursor.Hex(4);
  if (!options || !cursor.AtEnd()) return FrameErrorReply(kParameterCount);
  // BX also gives each tool's 3D marker positions (0x0008); TX is answered for 0x0001 and 0x0800 only.
  const uint32_t supported = name == "BX" ? 0x0809u : 0x0801u;
  if (!(*options & reply_option::kTransforms) || (*options & ~supported)) return FrameErrorReply(kOutOfRange);
  const uint32_t frame = FrameAt(TrackingTime(t_s));
  const std::optional<double> end_s = trajectory_->end_s();
  reply.past_end = end_s && TimeOfFrame(frame) > *end_s;
  TrackingReply tracking;
  for (const auto& [number, handle] : handles_) {
    if (!handle.initialised || handle.body < 0) continue;
    HandleReport report;
    if (handle.enabled) report = Report(handle.body, frame, static_cast<uint16_t>(*options));
    else report.status = HandleStatus::kDisabled;
    report.handle = number;
    tracking.handles.push_back(report);
  }
  reply.tracking_data = true;
  std::string bytes;
  if (name == "BX") {
    const std::vector<uint8_t> frame_bytes = EncodeBx(tracking, static_cast<uint16_t>(*options));
    bytes.assign(frame_bytes.begin(), frame_bytes.end());
  } else {
    bytes = FrameReply(EncodeTxText(tracking));
  }
  reply.served = std::move(tracking);
  return bytes;
}

HandleReport EmulatedTracker::Report(int body, uint32_t frame, uint16_t options) const {
  const BodyState truth = trajectory_->At(body, TimeOfFrame(frame));
  std::mt19937_64 rng = FrameRng(options_.seed, body, frame);
  std::normal_distribution<double> noise(0.0, options_.noise_mm);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  HandleReport report;
  report.has_port_status = true;
  report.port_status = kHealthyPort | truth.port_status_bits;
  report.frame_number = frame;
  const bool dropped = uniform(rng) < options_.dropout;
  Eigen::Vector3d t_mm = truth.T_tracker_body.translation() * 1e3;
  if (options_.noise_mm > 0) t_mm += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  if (options_.volume) {
    const Eigen::Vector3d p = truth.T_tracker_body.translation();
    const Eigen::Vector3d lo = p - options_.volume->min_m, hi = options_.volume->max_m - p;
    const double inside_by = std::min(lo.minCoeff(), hi.minCoeff());
    if (inside_by < 0) report.port_status |= port_status::kOutOfVolume;
    else if (inside_by < options_.volume->partial_margin_m) report.port_status |= port_status::kPartiallyInVolume;
  }
  const bool out_of_volume = report.port_status & port_status::kOutOfVolume;
  if (truth.forced_missing || dropped || (out_of_volume && !(options & reply_option::kOutOfVolume))) {
    report.status = HandleStatus::kMissing;
    return report;
  }
  const Eigen::Vector4d q = truth.T_tracker_body.quat_wxyz();
  report.status = HandleStatus::kValid;
  report.has_transform = true;
  report.q_wxyz = {q[0], q[1], q[2], q[3]};
  report.t_mm = {t_mm.x(), t_mm.y(), t_mm.z()};
  report.rms_error_mm = 0.1 + 0.5 * options_.noise_mm;
  if (options & reply_option::kToolMarkers) report.markers_mm = MarkersMm(truth.T_tracker_body, t_mm);
  return report;
}

// A tool's markers where the reported pose puts them: a planar, asymmetric pattern (as passive tools
// have, so that the fit is unique) of markers_per_tool points on a 40 mm circle, in the body frame.
std::vector<std::array<double, 3>> EmulatedTracker::MarkersMm(const Rigid3d& T_tracker_body, const Eigen::Vector3d& t_mm) const {
  std::vector<std::array<double, 3>> markers;
  for (int i = 0; i < options_.markers_per_tool; ++i) {
    const double angle = 2.0 * M_PI * i / options_.markers_per_tool + 0.3 * i * i;
    const Eigen::Vector3d p = T_tracker_body.rotation() * Eigen::Vector3d(40 * std::cos(angle), 40 * std::sin(angle), 0) + t_mm;
    markers.push_back({p.x(), p.y(), p.z()});
  }
  return markers;
}

}  // namespace mocap::ndi
