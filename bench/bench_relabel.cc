// The relabel a user runs (`mocaplabel relabel`; bench/RESULTS.md "Relabel"), end to end from files,
// through the binary as a user starts it: a simulated session of the default scenario (kFrames Kinect v1
// frames, 640x480) recorded once, then per iteration its label run removed and made again
// (--stages label, so every frame is stale):
//   label_single_pass/threads:T   `mocaplabel label S --threads T`: the one-process labeller, the
//                                 baseline a user has without relabel
//   relabel_local/jobs:J          `mocaplabel relabel S --stages label --jobs J --threads 1
//                                 --shard-frames kShardFrames`: J worker processes, then the merge
//   relabel_noop                  the same relabel with nothing stale: plan, export check, exit
// Counters: frames/s (wall clock).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/check.h"
#include "pipeline/subprocess.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;
constexpr int kFrames = 120, kShardFrames = 30;

struct Session {
  fs::path root, session;
  Session() : root(fs::temp_directory_path() / ("bench_relabel_" + std::to_string(::getpid()))) {
    fs::remove_all(root);
    fs::create_directories(root);
    session = root / "S";
    std::ifstream in(fs::path(MOCAP_SOURCE_DIR) / "scenarios/default.yaml");
    std::stringstream text;
    text << in.rdbuf();
    std::ofstream(root / "scenario.yaml") << std::regex_replace(text.str(), std::regex("frame_count: [0-9]+"),
                                                                "frame_count: " + std::to_string(kFrames));
    Run({"sim", "record", "--scenario", (root / "scenario.yaml").string(), "--out", session.string(), "--progress", "none"});
    Run({"label", session.string(), "--rig", (session / "rig.yaml").string(), "--objects",
         (session / "objects.yaml").string(), "--progress", "none"});
  }
  ~Session() { fs::remove_all(root); }
  static void Run(std::vector<std::string> args) {
    args.insert(args.begin(), MOCAPLABEL_EXE);
    const CommandOutput r = RunCommand(args);
    if (r.exit_code != 0) throw InputError(args[1], "failed: " + r.err + r.out);
  }
};

Session& TheSession() {
  static Session session;
  return session;
}

void Time(benchmark::State& state, const std::vector<std::string>& args, bool relabel_all) {
  Session& s = TheSession();
  for (auto _ : state) {
    state.PauseTiming();
    if (relabel_all) fs::remove_all(s.session / "labels");
    state.ResumeTiming();
    Session::Run(args);
  }
  state.counters["frames/s"] = benchmark::Counter(relabel_all ? kFrames : 0, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_LabelSinglePass(benchmark::State& state) {
  const Session& s = TheSession();
  Time(state, {"label", s.session.string(), "--threads", std::to_string(state.range(0)), "--progress", "none"}, true);
}
BENCHMARK(BM_LabelSinglePass)->Name("label_single_pass")->ArgName("threads")->Arg(1)->Arg(2)->Iterations(2)->UseRealTime()->Unit(benchmark::kSecond);

std::vector<std::string> RelabelArgs(int jobs) {
  const Session& s = TheSession();
  return {"relabel", s.session.string(), "--stages", "label", "--jobs", std::to_string(jobs), "--threads", "1",
          "--shard-frames", std::to_string(kShardFrames), "--work", (s.root / "work").string(), "--progress", "none"};
}

void BM_RelabelLocal(benchmark::State& state) { Time(state, RelabelArgs(static_cast<int>(state.range(0))), true); }
BENCHMARK(BM_RelabelLocal)->Name("relabel_local")->ArgName("jobs")->Arg(1)->Arg(2)->Iterations(2)->UseRealTime()->Unit(benchmark::kSecond);

void BM_RelabelNoop(benchmark::State& state) {
  Session::Run(RelabelArgs(2));  // whatever an earlier case left: labelled, nothing stale
  Time(state, RelabelArgs(2), false);
}
BENCHMARK(BM_RelabelNoop)->Name("relabel_noop")->Iterations(5)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mocap::pipeline

BENCHMARK_MAIN();
