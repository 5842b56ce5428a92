// `mocaplabel info S --json`: one JSON document on stdout with the documented keys; bad input exits 1
// with one line naming the problem.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "session/writer.h"
#include "session_test_util.h"

namespace mocap {
namespace {

struct CommandResult {
  int status = -1;
  std::string out;
};

CommandResult RunCommand(const std::string& command) {
  CommandResult run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  for (size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) run.out.append(buffer.data(), n);
  run.status = ::pclose(pipe);
  return run;
}

const std::string kBinary = std::string(MOCAP_BINARY_DIR) + "/src/cli/mocaplabel";

TEST(InfoCli, JsonDocumentHasTheDocumentedKeys) {
  testing::TempDir tmp;
  const auto dir = tmp.path() / "S";
  {
    auto writer = SessionWriter::Create(dir, testing::TwoCameraManifest());
    for (int i = 0; i < 3; ++i)
      writer->WriteCameraFrame("kinect1", {i, 0, i * 33'000'000, "", "", ""}, testing::TestColor(i, 8, 6),
                               testing::TestDepth(i, 8, 6));
    for (int k = 0; k < 10; ++k) {
      TrackerRecord record;
      record.body = "cam";
      record.stamp_ns = k * 10'000'000 + (k >= 5 ? 900'000'000 : 0);
      writer->WriteTrackerSample("ndi", record);
    }
  }
  const CommandResult run = RunCommand(kBinary + " info " + dir.string() + " --json");
  ASSERT_EQ(run.status, 0) << run.out;
  const nlohmann::json json = nlohmann::json::parse(run.out);
  EXPECT_EQ(json["frames"], 3);
  EXPECT_EQ(json["frames_with_pose"], 2);  // 0 and 33 ms lie within the samples; 66 ms is in the gap
  EXPECT_EQ(json["missing_files"], 0);
  EXPECT_TRUE(json["missing_file_list"].is_array());
  EXPECT_EQ(json["tracker_bodies"]["cam"]["samples"], 10);
  EXPECT_EQ(json["tracker_bodies"]["cam"]["duplicates"], 0);
  ASSERT_EQ(json["tracker_bodies"]["cam"]["gaps"].size(), 1u);
  EXPECT_EQ(json["tracker_bodies"]["cam"]["gaps"][0]["start_ns"], 40'000'000);
  EXPECT_EQ(json["tracker_bodies"]["cam"]["gaps"][0]["end_ns"], 950'000'000);
  EXPECT_TRUE(json["complete"].get<bool>());

  const CommandResult tight = RunCommand(kBinary + " info " + dir.string() + " --json --gap-limit 2");
  EXPECT_EQ(nlohmann::json::parse(tight.out)["tracker_bodies"]["cam"]["gaps"].size(), 0u);
  const CommandResult text = RunCommand(kBinary + " info " + dir.string());
  EXPECT_NE(text.out.find("frames with colour and depth: 3"), std::string::npos) << text.out;
}

TEST(InfoCli, MissingSessionExitsWithOneLine) {
  const CommandResult run = RunCommand(kBinary + " info /nonexistent/session 2>&1");
  EXPECT_EQ(WEXITSTATUS(run.status), 1);
  EXPECT_NE(run.out.find("/nonexistent/session: no such session folder"), std::string::npos) << run.out;
  EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1);
}

}  // namespace
}  // namespace mocap
