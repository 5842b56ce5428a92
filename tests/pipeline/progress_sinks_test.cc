#include "pipeline/progress_sinks.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>

#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli/progress_flag.h"
#include "core/check.h"
#include "core/log.h"

namespace mocap {
namespace {

/// Everything written to `file` so far, split into lines (the newline dropped).
std::vector<std::string> ReadLines(FILE* file) {
  std::fflush(file);
  std::rewind(file);
  std::vector<std::string> lines;
  std::string line;
  for (int c = std::fgetc(file); c != EOF; c = std::fgetc(file)) {
    if (c == '\n') {
      lines.push_back(line);
      line.clear();
    } else {
      line.push_back(static_cast<char>(c));
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

TEST(JsonProgressSink, OneParseableObjectPerUpdate) {
  FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    JsonProgressSink sink(file);
    Progress progress(&sink, "label", 3, "frames", 0.0);
    progress.Advance();
    progress.Advance(2);
  }  // the destructor's Finish() writes the last object
  const std::vector<std::string> lines = ReadLines(file);
  std::fclose(file);
  ASSERT_EQ(lines.size(), 3u);
  for (const std::string& line : lines) {
    const nlohmann::json object = nlohmann::json::parse(line);
    for (const char* field : {"progress", "done", "total", "unit", "elapsed_s", "rate_per_s", "eta_s", "finished"})
      EXPECT_TRUE(object.contains(field)) << field << " missing in " << line;
    EXPECT_EQ(object["progress"], "label");
    EXPECT_EQ(object["unit"], "frames");
    EXPECT_EQ(object["total"], 3);
  }
  EXPECT_EQ(nlohmann::json::parse(lines[0])["done"], 1);
  const nlohmann::json last = nlohmann::json::parse(lines[2]);
  EXPECT_EQ(last["done"], 3);
  EXPECT_EQ(last["finished"], true);
  EXPECT_EQ(last["eta_s"], 0.0);
}

TEST(JsonProgressSink, UnknownEtaIsNull) {
  FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  JsonProgressSink sink(file);
  sink.Report({"import", 4, 0, "records", 1.0, 4.0, -1, false});
  const std::vector<std::string> lines = ReadLines(file);
  std::fclose(file);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_TRUE(nlohmann::json::parse(lines[0])["eta_s"].is_null());
}

TEST(TerminalProgressSink, NonTerminalGetsOnlyTheFinalLine) {
  FILE* file = std::tmpfile();
  ASSERT_NE(file, nullptr);
  {
    TerminalProgressSink sink(file);
    Progress progress(&sink, "validate", 300, "frames", 0.0);
    for (int i = 0; i < 300; ++i) progress.Advance();
    progress.Finish();
  }
  const std::vector<std::string> lines = ReadLines(file);
  std::fclose(file);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].find('\r'), std::string::npos);
  EXPECT_EQ(lines[0].rfind("validate  300/300 frames  ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find("done in"), std::string::npos) << lines[0];
}

TEST(FormatProgressLine, ShowsCountRateAndTimeLeft) {
  EXPECT_EQ(FormatProgressLine({"label", 120, 300, "frames", 2.66, 45.1, 4.0, false}),
            "label  120/300 frames  45.1 frames/s  4 s left");
  EXPECT_EQ(FormatProgressLine({"import", 7, 0, "records", 1.0, 7.0, -1, false}), "import  7 records  7.0 records/s");
  EXPECT_EQ(FormatProgressLine({"demo", 1, 10, "shards", 1.0, 1.0, 200.0, false}),
            "demo  1/10 shards  1.0 shards/s  3 min 20 s left");
}

TEST(ProgressMode, ParsesTheFourNamesAndRejectsOthers) {
  EXPECT_EQ(ProgressModeFromString("auto"), ProgressMode::kAuto);
  EXPECT_EQ(ProgressModeFromString("terminal"), ProgressMode::kTerminal);
  EXPECT_EQ(ProgressModeFromString("json"), ProgressMode::kJson);
  EXPECT_EQ(ProgressModeFromString("none"), ProgressMode::kNone);
  try {
    ProgressModeFromString("fancy");
    FAIL() << "accepted 'fancy'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("auto, terminal, json or none"), std::string::npos) << e.what();
  }
  EXPECT_EQ(MakeProgressSink(ProgressMode::kNone), nullptr);
  EXPECT_NE(MakeProgressSink(ProgressMode::kJson), nullptr);
}

// Points the log at a string stream for the test's length, then back at stderr in text mode.
class LogCapture : public ::testing::Test {
 protected:
  void SetUp() override { SetLogSinkForTest(std::make_shared<spdlog::sinks::ostream_sink_mt>(out_)); }
  void TearDown() override {
    SetLogJson(false);
    SetLogLevel("info");
    SetLogSinkForTest(nullptr);
  }
  std::vector<std::string> Lines() {
    std::vector<std::string> lines;
    std::istringstream in(out_.str());
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
  }
  std::ostringstream out_;
};

TEST_F(LogCapture, TextLinesCarryThePrefixAndLevel) {
  Log().warn("capture: recording {}", "/tmp/s1");
  Log().debug("not shown at info");
  ASSERT_EQ(Lines().size(), 1u);
  EXPECT_EQ(Lines()[0], "mocaplabel: [warning] capture: recording /tmp/s1");
}

TEST_F(LogCapture, JsonModeWritesParseableLines) {
  SetLogJson(true);
  Log().info("session {} left incomplete: {}", "/tmp/a \"quoted\"\tdir", "disk full\nreally");
  Log().error("second");
  const std::vector<std::string> lines = Lines();
  ASSERT_EQ(lines.size(), 2u);
  const nlohmann::json first = nlohmann::json::parse(lines[0]);
  EXPECT_EQ(first["level"], "info");
  EXPECT_EQ(first["msg"], "session /tmp/a \"quoted\"\tdir left incomplete: disk full\nreally");
  const std::string time = first["time_utc"];
  EXPECT_EQ(time.size(), 24u) << time;  // 2026-12-02T06:43:26.123Z
  EXPECT_EQ(time.back(), 'Z');
  EXPECT_EQ(nlohmann::json::parse(lines[1])["level"], "error");
}

TEST_F(LogCapture, LevelFiltersAndUnknownNamesAreRejected) {
  SetLogLevel("error");
  Log().warn("hidden");
  Log().error("shown");
  EXPECT_EQ(Lines().size(), 1u);
  try {
    SetLogLevel("loud");
    FAIL() << "accepted 'loud'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("trace, debug, info, warn, error, critical or off"), std::string::npos);
  }
}

TEST_F(LogCapture, ProgressFlagsSetLogAndSink) {
  CLI::App app;
  cli::ProgressFlags flags;
  cli::AddProgressFlags(app, flags);
  const char* argv[] = {"test", "--progress", "json", "--log-level", "debug"};
  app.parse(5, argv);
  EXPECT_EQ(flags.progress, "json");
  const std::unique_ptr<ProgressSink> sink = cli::ApplyProgressFlags(flags);
  EXPECT_NE(dynamic_cast<JsonProgressSink*>(sink.get()), nullptr);
  Log().debug("now shown");
  ASSERT_EQ(Lines().size(), 1u);
  EXPECT_EQ(nlohmann::json::parse(Lines()[0])["msg"], "now shown");

  flags = {"none", "warn"};
  EXPECT_EQ(cli::ApplyProgressFlags(flags), nullptr);
  flags = {"bogus", "info"};
  EXPECT_THROW(cli::ApplyProgressFlags(flags), InputError);
}

}  // namespace
}  // namespace mocap
