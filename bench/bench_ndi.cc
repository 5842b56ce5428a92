// NDI tracker throughput: how many BX replies (tracker samples) per second the client side can parse
// and convert, and how many BX request/reply exchanges per second run over TCP loopback against the
// emulator. Goal (capture daemon): 10x a 400 Hz tracker = 4000 samples/s.
#include <benchmark/benchmark.h>

#include <memory>

#include "capture/ndi/commands.h"
#include "capture/ndi/convert.h"
#include "capture/ndi/emulator.h"
#include "capture/ndi/encode.h"
#include "capture/ndi/link.h"
#include "capture/ndi/reply.h"

namespace mocap::ndi {
namespace {

std::vector<uint8_t> BxWithHandles(int count) {
  TrackingReply reply;
  for (int i = 0; i < count; ++i) {
    HandleReport h;
    h.handle = i + 1;
    h.status = HandleStatus::kValid;
    h.has_transform = true;
    h.q_wxyz = {0.7071, 0.7071, 0, 0};
    h.t_mm = {10.0 * i, -20.25, -1500};
    h.rms_error_mm = 0.12;
    h.port_status = 0x31;
    h.frame_number = 123456;
    reply.handles.push_back(h);
  }
  return EncodeBx(reply);
}

// Parse (CRC-checked) and convert every body to Rigid3d + PoseStatus, as the client does per reply.
void BM_ParseAndConvertBx(benchmark::State& state) {
  const std::vector<uint8_t> frame = BxWithHandles(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const Parsed<TrackingReply> reply = ParseBx(frame, 0x0801);
    for (const HandleReport& h : reply.value->handles) {
      benchmark::DoNotOptimize(ToRigid3d(h));
      benchmark::DoNotOptimize(ToPoseStatus(h));
    }
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ParseAndConvertBx)->Arg(1)->Arg(4)->Arg(16);

// BX:0801 request/reply exchanges over TCP loopback against the emulator (unthrottled polling).
void BM_BxRoundTripLoopback(benchmark::State& state) {
  Emulator emulator({.port = 0, .tracker = {.rate_hz = 1000}},
                    std::make_shared<ScriptedTrajectory>(DefaultTrajectoryScript(static_cast<int>(state.range(0)))));
  emulator.Start();
  Link link(ConnectTcp("127.0.0.1", emulator.port(), 1000));
  link.Command("INIT:", 1000);
  for (int handle = 1; handle <= state.range(0); ++handle) {
    link.Command(PinitCommand(handle), 1000);
    link.Command(PenaCommand(handle, ToolMode::kDynamic), 1000);
  }
  link.Command("TSTART:", 1000);
  for (auto _ : state) benchmark::DoNotOptimize(link.Bx(0x0801, 1000));
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BxRoundTripLoopback)->Arg(4)->UseRealTime();

}  // namespace
}  // namespace mocap::ndi

BENCHMARK_MAIN();
