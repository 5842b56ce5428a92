#include "tests/exporters/bop/export_fixture.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "tests/kinect/subprocess.h"

namespace mocap::testing {
namespace fs = std::filesystem;

int Mocaplabel(const std::vector<std::string>& args, std::string* output) {
  std::vector<std::string> argv = {MOCAPLABEL_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  const fs::path log = fs::temp_directory_path() / ("mocaplabel_export_" + std::to_string(::getpid()) + ".log");
  const ProcessResult r = RunProcess(argv, {}, log);
  if (output) *output = r.output;
  return r.exit_code;
}

LabelledSession MakeLabelledSession(const std::string& name, int frames, const std::string& sensor) {
  LabelledSession s;
  s.dir = fs::temp_directory_path() / ("mocaplabel_export_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(s.dir);
  fs::create_directories(s.dir);
  std::ifstream in(fs::path(MOCAP_SOURCE_DIR) / "scenarios/default.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string scenario = std::regex_replace(text.str(), std::regex("frame_count: [0-9]+"), "frame_count: " + std::to_string(frames));
  scenario = std::regex_replace(scenario, std::regex("\nsensor: kinect1"), "\nsensor: " + sensor);
  std::ofstream(s.dir / "scenario.yaml") << scenario;
  s.session = s.dir / "S", s.labels = s.dir / "S" / "labels";
  std::string output;
  EXPECT_EQ(Mocaplabel({"sim", "record", "--scenario", (s.dir / "scenario.yaml").string(), "--out", s.session.string()}, &output), 0) << output;
  EXPECT_EQ(Mocaplabel({"label", s.session.string()}, &output), 0) << output;
  return s;
}

}  // namespace mocap::testing
