#include "tests/relabel/relabel_fixture.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "pipeline/object_library.h"
#include "tests/kinect/subprocess.h"

namespace mocap::testing {
namespace fs = std::filesystem;

namespace {

std::string ReadText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

int Mocaplabel(const std::vector<std::string>& args, std::string* output, const std::map<std::string, std::string>& env) {
  std::vector<std::string> argv = {MOCAPLABEL_EXE};
  argv.insert(argv.end(), args.begin(), args.end());
  const fs::path log = fs::temp_directory_path() / ("mocaplabel_relabel_" + std::to_string(::getpid()) + ".log");
  const ProcessResult r = RunProcess(argv, env, log);
  if (output) *output = r.output;
  return r.exit_code;
}

nlohmann::json LastJson(const std::string& output) {
  std::istringstream lines(output);
  nlohmann::json last;
  for (std::string line; std::getline(lines, line);)
    if (!line.empty() && line.front() == '{') {
      try {
        last = nlohmann::json::parse(line);
      } catch (const nlohmann::json::exception&) {
      }
    }
  return last;
}

RelabelSessions MakeRelabelSessions(const std::string& name, const std::vector<std::vector<std::string>>& left_out,
                                    int frames) {
  RelabelSessions s;
  s.dir = fs::temp_directory_path() / ("mocaplabel_relabel_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(s.dir);
  fs::create_directories(s.dir);
  const std::string base = std::regex_replace(ReadText(fs::path(MOCAP_SOURCE_DIR) / "scenarios/default.yaml"),
                                              std::regex("frame_count: [0-9]+"), "frame_count: " + std::to_string(frames));
  for (size_t i = 0; i < left_out.size(); ++i) {
    std::string scenario = base;
    for (const std::string& object : left_out[i])  // the object's block: its name line and its keyframes
      scenario = std::regex_replace(scenario, std::regex("  - name: " + object + "\n    keyframes:\n(      - .*\n)+"), "");
    const fs::path file = s.dir / ("scenario" + std::to_string(i) + ".yaml");
    std::ofstream(file) << scenario;
    s.sessions.push_back(s.dir / ("S" + std::to_string(i + 1)));
    std::string output;
    EXPECT_EQ(Mocaplabel({"sim", "record", "--scenario", file.string(), "--out", s.sessions.back().string()}, &output), 0) << output;
  }
  // One rig and one object library for all, as a lab has them.
  s.rig = s.dir / "rig.yaml", s.objects = s.dir / "objects.yaml";
  fs::copy_file(s.sessions[0] / "rig.yaml", s.rig);
  fs::copy(s.sessions[0] / "meshes", s.dir / "meshes", fs::copy_options::recursive);
  fs::copy_file(s.sessions[0] / "objects.yaml", s.objects);
  return s;
}

std::map<std::string, std::string> TreeFiles(const fs::path& dir) {
  static const std::vector<std::string> skip = {"run.json", "label_manifest.json", "validation.json", "report.html", "export.json"};
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && std::find(skip.begin(), skip.end(), name) == skip.end())
      files[fs::relative(e.path(), dir).string()] = ReadText(e.path());
  }
  return files;
}

void ShiftMount(const fs::path& objects_yaml, const std::string& object, double dz_m) {
  pipeline::ObjectLibrary library = pipeline::ReadObjectLibrary(objects_yaml);
  bool found = false;
  for (pipeline::LibraryObject& o : library.objects)
    if (o.name == object) {
      Rigid3d& T = o.mounts.at(0).T_body_mesh;
      T = Rigid3d(T.rotation(), T.translation() + Eigen::Vector3d(0, 0, dz_m));
      found = true;
    }
  ASSERT_TRUE(found) << object;
  pipeline::WriteObjectLibrary(library, objects_yaml);
}

}  // namespace mocap::testing
