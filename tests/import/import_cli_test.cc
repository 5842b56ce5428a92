// The importers through the binary, as a user runs them: `mocaplabel import ... --json` then
// `mocaplabel info S --json`; bad input exits 1 with one line naming the file and position.
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "test_util.h"

namespace mocap::import {
namespace {

using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

struct CommandResult {
  int exit_code = -1;
  std::string out;
};

CommandResult Mocaplabel(const std::string& arguments) {
  const std::string command = std::string(MOCAP_BINARY_DIR) + "/src/cli/mocaplabel " + arguments;
  CommandResult run;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buffer;
  for (size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0;) run.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

nlohmann::json Json(const CommandResult& run) {
  EXPECT_EQ(run.exit_code, 0) << run.out;
  return nlohmann::json::parse(run.out);
}

TEST(ImportCli, TumThenInfo) {
  ScratchDir scratch;
  const auto session = (scratch.path() / "S").string();
  const auto imported = Json(Mocaplabel("import tum " + RealData("tum_fr1_desk_9frames").string() + " --out " + session + " --json"));
  EXPECT_EQ(imported["frames"], 9);
  const auto info = Json(Mocaplabel("info " + session + " --json"));
  EXPECT_EQ(info["frames"], 9);
  EXPECT_EQ(info["frames_with_pose"], 9);
  EXPECT_EQ(info["missing_files"], (613 - 9) + (595 - 9));
  EXPECT_EQ(info["tracker_bodies"]["camera"]["samples"], 2335);
}

TEST(ImportCli, Fr2DeskGapsAndDuplicateInInfo) {
  ScratchDir scratch;
  const auto session = (scratch.path() / "S").string();
  Json(Mocaplabel("import tum " + RealData("tum_groundtruth_evo/fr2_desk_groundtruth.txt").string() + " --out " + session + " --json"));
  const auto info = Json(Mocaplabel("info " + session + " --json"));
  EXPECT_EQ(info["tracker_bodies"]["camera"]["duplicates"], 1);
  EXPECT_EQ(info["tracker_bodies"]["camera"]["gaps"].size(), 6u);
}

TEST(ImportCli, PlusMotiveAndBop) {
  ScratchDir scratch;
  const auto plus = Json(Mocaplabel("import plus " + RealData("plus_ndi_tracking/TransformInterpolationTest.igs.mha").string() +
                             " --out " + (scratch.path() / "P").string() + " --json"));
  EXPECT_EQ(plus["tracker_bodies"]["plus/Probe"]["status_counts"]["missing"], 1);
  const auto motive = Json(Mocaplabel("import motive " + RealData("optitrack_neon_calib/optitrack_take.csv").string() + " --out " +
                               (scratch.path() / "M").string() + " --json"));
  EXPECT_EQ(motive["tracker_samples"], 2 * 241);
  const auto bop = Json(Mocaplabel("import bop " + RealData("bop_lmo_scene2/test/000002").string() + " --models " +
                            RealData("bop_lmo_scene2/models").string() + " --out " + (scratch.path() / "B").string() + " --json"));
  EXPECT_EQ(bop["camera_records"], 10);
  EXPECT_TRUE(std::filesystem::exists(scratch.path() / "B" / "objects.yaml"));
  // The BOP test subset ships 10 of 59 images: the 49 it leaves out are not drops.
  const auto info = Json(Mocaplabel("info " + (scratch.path() / "B").string() + " --json"));
  EXPECT_EQ(info["cameras"]["bop"]["dropped_frames"], 0);
  EXPECT_EQ(info["cameras"]["bop"]["frames_subset"], true);
  const CommandResult text = Mocaplabel("info " + (scratch.path() / "B").string());
  EXPECT_EQ(text.out.find("dropped"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("chosen subset"), std::string::npos) << text.out;
}

TEST(ImportCli, BadInputExitsWithOneLine) {
  ScratchDir scratch;
  std::string csv = ReadAll(RealData("optitrack_neon_calib/optitrack_take.csv"));
  csv.resize(csv.size() / 2);  // cut in the middle of a row
  const auto file = scratch.Write("cut.csv", csv);
  const CommandResult run = Mocaplabel("import motive " + file.string() + " --out " + (scratch.path() / "S").string() + " 2>&1");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.out.find("cut.csv:"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("(truncated file?)"), std::string::npos) << run.out;
  EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "S"));
}

TEST(ImportCli, NumberFlagsAreRangeCheckedNamingTheFlag) {
  ScratchDir scratch;
  const std::string out = " --out " + (scratch.path() / "S").string() + " 2>&1";
  const std::string tum = "import tum " + RealData("tum_fr1_desk_9frames").string();
  const std::string bop = "import bop " + RealData("bop_lmo_scene2/test/000002").string() + " --models " +
                          RealData("bop_lmo_scene2/models").string();
  for (const auto& [arguments, flag] : std::vector<std::pair<std::string, std::string>>{
           {bop + " --rate 1e300", "--rate: "},
           {tum + " --intrinsics 1e308,525,319.5,239.5", "--intrinsics fx: "},
           {tum + " --depth-factor 0", "--depth-factor: "},
           {tum + " --depth-factor 1e300", "--depth-factor: "},
           {tum + " --gap-limit 1e300", "--gap-limit: "},
           {tum + " --max-difference 1e300", "--max-difference: "}}) {
    const CommandResult run = Mocaplabel(arguments + out);
    EXPECT_EQ(run.exit_code, 1) << arguments;
    EXPECT_NE(run.out.find(flag + "must be between"), std::string::npos) << run.out;
    EXPECT_EQ(run.out.find("Options"), std::string::npos) << run.out;
    EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
  }
  EXPECT_FALSE(std::filesystem::exists(scratch.path() / "S"));
  // stdout alone: stderr carries the progress line (docs/progress.md).
  const auto summary = Json(Mocaplabel(tum + " --depth-factor 1000 --json --out " + (scratch.path() / "S").string()));
  EXPECT_GT(summary["frames"].get<int>(), 0);
}

}  // namespace
}  // namespace mocap::import
