#include "cli_run.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "tests/kinect/subprocess.h"

namespace mocap::test {

namespace fs = std::filesystem;
using nlohmann::json;

int Mocaplabel(const std::vector<std::string>& args, std::string* out) {
  std::vector<std::string> argv = {MOCAPLABEL_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  const testing::ProcessResult r =
      testing::RunProcess(argv, {}, fs::temp_directory_path() / ("calibrate_cli_" + std::to_string(::getpid()) + ".log"));
  *out = r.output;
  return r.exit_code;
}

json LastJson(const std::string& output) {
  std::istringstream lines(output);
  json last;
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line[0] == '{') last = json::parse(line, nullptr, false);
  return last;
}

std::string ReadText(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Rigid3d PoseOf(const json& j) {
  const auto& q = j["rotation_wxyz"];
  const auto& t = j["translation_m"];
  return Rigid3d(Eigen::Quaterniond(q[0], q[1], q[2], q[3]), Eigen::Vector3d(t[0], t[1], t[2]));
}

Rigid3d TruthPoseOf(const json& j) {
  const auto& q = j["q_wxyz"];
  const auto& t = j["t_m"];
  return Rigid3d(Eigen::Quaterniond(q[0], q[1], q[2], q[3]), Eigen::Vector3d(t[0], t[1], t[2]));
}

}  // namespace mocap::test
