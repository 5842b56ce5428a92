// Crash safety: a writer killed with SIGKILL mid-stream, and a writer whose disk fills up.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <map>
#include <thread>

#include "session/reader.h"
#include "session/writer.h"
#include "full_disk.h"
#include "session_test_util.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using testing::TempDir;

int64_t MonotonicNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Report {
  int64_t index;
  int64_t returned_ns;  ///< when the Write* calls of this index had returned
};

/// The child: writes frame i, tracker samples and an event for i = 0, 1, ... and reports each i on
/// `fd` once its calls returned; runs until killed.
[[noreturn]] void WriteForever(const fs::path& dir, int fd) {
  SessionWriterOptions options;
  options.encoder_threads = 2;
  auto writer = SessionWriter::Create(dir, testing::TwoCameraManifest(), options);
  const cv::Mat depth = testing::TestDepth(0, 320, 240);
  for (int64_t i = 0;; ++i) {
    writer->WriteCameraFrame("kinect1", {i, i * 2'000'000, MonotonicNs(), "", "", ""},
                             testing::TestColor(static_cast<int>(i), 320, 240), depth);
    TrackerRecord sample;
    sample.body = "cam";
    sample.device_frame = i;
    sample.stamp_ns = MonotonicNs();
    sample.T_frame_body = Rigid3d::FromRvec({0.001 * static_cast<double>(i), 0, 0}, {0, 0, 1});
    writer->WriteTrackerSample("ndi", sample);
    writer->WriteEvent({MonotonicNs(), "note", "", std::to_string(i)});
    const Report report{i, MonotonicNs()};
    if (::write(fd, &report, sizeof(report)) != sizeof(report)) ::_exit(3);
    std::this_thread::sleep_for(std::chrono::milliseconds(4));
  }
}

TEST(CrashSafety, SigkillMidStreamKeepsEverythingFlushedBeforeTheLastSecond) {
  TempDir tmp;
  const fs::path dir = tmp.path() / "S";
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(fds[0]);
    WriteForever(dir, fds[1]);
  }
  ::close(fds[1]);
  std::vector<Report> reports;
  const int64_t start_ns = MonotonicNs();
  while (MonotonicNs() - start_ns < 2'200'000'000) {
    Report report{};
    if (::read(fds[0], &report, sizeof(report)) != sizeof(report)) break;
    reports.push_back(report);
  }
  const int64_t kill_ns = MonotonicNs();
  ASSERT_EQ(::kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "the writer died before the kill";
  ::close(fds[0]);
  ASSERT_GT(reports.size(), 20u) << "the child wrote too little to test anything";

  const SessionReader reader = SessionReader::Open(dir);
  EXPECT_FALSE(reader.complete());
  // Records hold a prefix 0..n-1 of what was handed over, in order, each frame's images whole.
  const int64_t frames = reader.frame_count("kinect1");
  for (int64_t i = 0; i < frames; ++i) {
    ASSERT_EQ(reader.frame("kinect1", i).record.frame, i);
    ASSERT_TRUE(reader.frame("kinect1", i).color_present && reader.frame("kinect1", i).depth_present);
  }
  for (int64_t i : {int64_t{0}, frames / 2, frames - 1}) {
    if (i < 0) continue;
    EXPECT_EQ(reader.LoadColor("kinect1", i).cols, 320);
    EXPECT_EQ(reader.LoadDepth("kinect1", i).width, 320);
  }
  const auto samples = reader.tracker_records("ndi");
  for (size_t i = 0; i < samples.size(); ++i) ASSERT_EQ(samples[i].device_frame, static_cast<int64_t>(i));
  // Every index handed over more than a second before the kill is there.
  int64_t required = 0;
  for (const Report& report : reports)
    if (report.returned_ns < kill_ns - 1'000'000'000) required = report.index + 1;
  EXPECT_GT(required, 10);
  EXPECT_GE(frames, required);
  EXPECT_GE(static_cast<int64_t>(samples.size()), required);
  EXPECT_GE(static_cast<int64_t>(reader.events().size()), required);
  std::printf("handed over %zu, required %lld, found %lld frames %zu samples %zu events\n", reports.size(),
              static_cast<long long>(required), static_cast<long long>(frames), samples.size(),
              reader.events().size());
}

/// In a child with its own mount namespace, mounts a 1 MiB tmpfs and writes until the disk is full.
/// Returns "SKIP ..." when a tmpfs cannot be mounted, "OK ..." or a failure description.
std::string FillDiskInChild(const fs::path& mount_point) {
  return testing::RunOnFullDiskInChild(mount_point, [&](const testing::SayFn& say) {
    std::string error;
    try {
      auto writer = SessionWriter::Create(mount_point / "S", testing::TwoCameraManifest());
      cv::Mat noise(240, 320, CV_8UC3);
      for (int i = 0; i < 1000; ++i) {
        cv::randu(noise, 0, 255);  // incompressible: fills the disk fast
        writer->WriteCameraFrame("kinect1", {i, 0, i, "", "", ""}, noise, cv::Mat());
      }
      writer->Close();
    } catch (const InputError& e) {
      error = e.what();
    }
    if (error.find("No space left on device") == std::string::npos) say("FAIL expected ENOSPC, got: " + error);
    if (error.find(mount_point.string()) == std::string::npos) say("FAIL error does not name the file: " + error);
    try {
      const SessionReader reader = SessionReader::Open(mount_point / "S");
      for (int64_t i = 0; i < reader.frame_count("kinect1"); ++i) reader.LoadColor("kinect1", i);
      say("OK " + std::to_string(reader.frame_count("kinect1")) + " whole frames; error: " + error);
    } catch (const std::exception& e) {
      say(std::string("FAIL reading the full session: ") + e.what());
    }
  });
}

TEST(CrashSafety, FullDiskRaisesErrorAndLeavesOnlyWholeFrames) {
  TempDir tmp;
  const std::string result = FillDiskInChild(tmp.path());
  if (result.rfind("SKIP", 0) == 0) GTEST_SKIP() << result;
  EXPECT_EQ(result.rfind("OK", 0), 0u) << result;
  std::printf("%s\n", result.c_str());
}

}  // namespace
}  // namespace mocap
