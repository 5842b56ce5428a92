#include "core/progress.h"

#include <gtest/gtest.h>

#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "core/check.h"

namespace mocap {
namespace {

// Keeps every update; Report() is called under the Progress's lock, the mutex guards the test's reads.
class RecordingSink : public ProgressSink {
 public:
  void Report(const ProgressUpdate& update) override {
    std::lock_guard lock(mutex);
    updates.push_back(update);
  }
  std::mutex mutex;
  std::vector<ProgressUpdate> updates;
};

void AdvanceFromThreads(Progress& progress, int threads, int per_thread) {
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&progress, per_thread] {
      for (int i = 0; i < per_thread; ++i) progress.Advance();
    });
  }
  for (std::thread& worker : workers) worker.join();
}

TEST(Progress, ManyThreadsReportMonotoneDoneAndEndAtTotal) {
  RecordingSink sink;
  {
    Progress progress(&sink, "label", 10000, "frames", 0.0);  // no rate limit: as many reports as possible
    AdvanceFromThreads(progress, 8, 1250);
    progress.Finish();
  }
  ASSERT_GE(sink.updates.size(), 2u);
  for (size_t i = 1; i < sink.updates.size(); ++i) EXPECT_GE(sink.updates[i].done, sink.updates[i - 1].done);
  const ProgressUpdate& last = sink.updates.back();
  EXPECT_EQ(last.done, 10000);
  EXPECT_EQ(last.total, 10000);
  EXPECT_TRUE(last.finished);
  EXPECT_EQ(last.task, "label");
  EXPECT_EQ(last.unit, "frames");
  EXPECT_DOUBLE_EQ(last.eta_s, 0.0);
  EXPECT_GE(last.elapsed_s, 0.0);
  for (size_t i = 0; i + 1 < sink.updates.size(); ++i) EXPECT_FALSE(sink.updates[i].finished);
}

TEST(Progress, RateLimitLeavesFirstTotalAndFinish) {
  RecordingSink sink;
  {
    Progress progress(&sink, "validate", 10000, "frames", 3600.0);
    AdvanceFromThreads(progress, 8, 1250);
  }  // the destructor finishes
  ASSERT_EQ(sink.updates.size(), 3u);
  EXPECT_GE(sink.updates[0].done, 1);  // the first update, at once
  EXPECT_FALSE(sink.updates[0].finished);
  EXPECT_EQ(sink.updates[1].done, 10000);  // the one that reached the total
  EXPECT_FALSE(sink.updates[1].finished);
  EXPECT_EQ(sink.updates[2].done, 10000);
  EXPECT_TRUE(sink.updates[2].finished);
}

TEST(Progress, FinishReportsOnceAndStopsReports) {
  RecordingSink sink;
  Progress progress(&sink, "import", 0, "records", 0.0);  // total unknown
  progress.Advance(5);
  progress.Finish();
  progress.Finish();
  progress.Advance(3);
  ASSERT_EQ(sink.updates.size(), 2u);
  EXPECT_EQ(sink.updates[0].done, 5);
  EXPECT_DOUBLE_EQ(sink.updates[0].eta_s, -1.0);  // unknown without a total
  EXPECT_TRUE(sink.updates[1].finished);
  EXPECT_EQ(progress.done(), 8);  // still counted, just not reported
}

TEST(Progress, EtaFromTheRateSoFar) {
  RecordingSink sink;
  Progress progress(&sink, "sim record", 100, "frames", 0.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  progress.Advance(10);
  ASSERT_EQ(sink.updates.size(), 1u);
  const ProgressUpdate& update = sink.updates[0];
  EXPECT_GT(update.rate_per_s, 0.0);
  EXPECT_NEAR(update.eta_s, 90.0 / update.rate_per_s, 1e-9);
  EXPECT_NEAR(update.rate_per_s, 10.0 / update.elapsed_s, 1e-9);
}

TEST(Progress, NullSinkIsANoOp) {
  Progress progress(nullptr, "label", 100);
  AdvanceFromThreads(progress, 4, 25);
  progress.Finish();
  EXPECT_EQ(progress.done(), 0);  // not even counted: nobody listens
}

TEST(Progress, RejectsBadOptions) {
  EXPECT_THROW(Progress(nullptr, "label", -1), InputError);
  EXPECT_THROW(Progress(nullptr, "label", 10, "frames", -0.5), InputError);
}

}  // namespace
}  // namespace mocap
