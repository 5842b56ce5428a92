// Cost of telling whether a run is stale (pipeline/provenance.h) on a session-sized input tree:
// 20 000 files of 4 KiB plus 4 files of 32 MiB (about 210 MiB) under a temp folder.
// Run: build/bench/bench_provenance; results go into bench/RESULTS.md ("bench_provenance").
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "pipeline/provenance.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr int kSmallFiles = 20000;
constexpr size_t kSmallBytes = 4096;
constexpr int kLargeFiles = 4;
constexpr size_t kLargeBytes = size_t{32} << 20;

void SetAllMtimes(const fs::path& root, std::chrono::seconds age) {
  const auto when = fs::file_time_type::clock::now() - age;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file()) fs::last_write_time(entry.path(), when);
  }
}

// The tree, a run recorded before every file was touched (same bytes, other mtimes) and one recorded
// after, and a cache folder holding the hashes of the touched files. Built once, removed at exit.
struct Tree {
  fs::path root, cache_dir;
  RunProvenance before_touch, after_touch;
  int64_t files = 0;
  uint64_t bytes = 0;

  Tree() {
    root = fs::temp_directory_path() / ("mocap_bench_provenance_" + std::to_string(::getpid()));
    cache_dir = root / "cache";
    fs::remove_all(root);
    std::string block(kLargeBytes, '\0');
    for (size_t i = 0; i < block.size(); ++i) block[i] = static_cast<char>((i * 2654435761u) >> 11);
    for (int i = 0; i < kSmallFiles; ++i) {
      const fs::path file = root / "tree" / std::to_string(i / 100) / (std::to_string(i) + ".bin");
      fs::create_directories(file.parent_path());
      std::ofstream(file, std::ios::binary).write(block.data() + i, kSmallBytes);
    }
    for (int i = 0; i < kLargeFiles; ++i) {
      std::ofstream(root / "tree" / ("large" + std::to_string(i) + ".bin"), std::ios::binary)
          .write(block.data(), static_cast<std::streamsize>(kLargeBytes - i));
    }
    SetAllMtimes(root / "tree", std::chrono::hours(2));  // old enough for the stat fast path
    HashCache memory_only(fs::path{});
    before_touch.inputs = FingerprintInputs({{"session", root / "tree", true, {}}}, memory_only);
    SetAllMtimes(root / "tree", std::chrono::hours(1));  // `touch` without changing a byte
    HashCache on_disk(cache_dir);
    after_touch.inputs = FingerprintInputs({{"session", root / "tree", true, {}}}, on_disk);
    files = after_touch.inputs[0].files;
    bytes = after_touch.inputs[0].size_bytes;
  }
  ~Tree() { fs::remove_all(root); }
};

const Tree& TheTree() {
  static const Tree tree;
  return tree;
}

void Report(benchmark::State& state, const Tree& tree, const StaleReport& report) {
  state.counters["files/s"] =
      benchmark::Counter(static_cast<double>(tree.files), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["files_hashed"] = static_cast<double>(report.files_hashed);
  state.counters["stale"] = report.stale ? 1 : 0;
}

// The fast path: every file's size and mtime as recorded, so the tree's stat digest vouches for it.
void BM_CheckStaleUnchanged(benchmark::State& state) {
  const Tree& tree = TheTree();
  HashCache cache(fs::path{});
  StaleReport report;
  for (auto _ : state) report = CheckStale(tree.after_touch, {}, cache);
  Report(state, tree, report);
}
BENCHMARK(BM_CheckStaleUnchanged)->Unit(benchmark::kMillisecond)->UseRealTime();

// Every file touched since the run: a stat and a lookup in the hash cache per file, as a new process
// does it (the cache file loaded from disk in every iteration).
void BM_CheckStaleTouchedCacheFromDisk(benchmark::State& state) {
  const Tree& tree = TheTree();
  StaleReport report;
  for (auto _ : state) {
    HashCache cache(tree.cache_dir);
    report = CheckStale(tree.before_touch, {}, cache);
  }
  Report(state, tree, report);
}
BENCHMARK(BM_CheckStaleTouchedCacheFromDisk)->Unit(benchmark::kMillisecond)->UseRealTime();

// Touched, and no cache (another machine, a cleared cache): every byte read and hashed (page cache
// warm, so this is the hashing cost, not the disk's).
void BM_CheckStaleTouchedNoCache(benchmark::State& state) {
  const Tree& tree = TheTree();
  StaleReport report;
  for (auto _ : state) {
    HashCache cache(fs::path{});
    report = CheckStale(tree.before_touch, {}, cache);
  }
  Report(state, tree, report);
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * tree.bytes));
}
BENCHMARK(BM_CheckStaleTouchedNoCache)->Unit(benchmark::kMillisecond)->UseRealTime();

// One 32 MiB file hashed from the page cache: XXH3-128 streaming throughput.
void BM_HashFileXxh3Large(benchmark::State& state) {
  const Tree& tree = TheTree();
  const fs::path file = tree.root / "tree" / "large0.bin";
  for (auto _ : state) benchmark::DoNotOptimize(HashFileXxh3(file));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * fs::file_size(file)));
}
BENCHMARK(BM_HashFileXxh3Large)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace mocap::pipeline

BENCHMARK_MAIN();
