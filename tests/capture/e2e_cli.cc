#include "e2e_cli.h"

#include <optional>
#include <stdexcept>

namespace mocap::testing {

namespace fs = std::filesystem;

nlohmann::json FirstJsonLine(ChildProcess& process, const std::string& what) {
  const std::optional<std::string> line = process.ReadLine(30000);  // devices opened first; a loaded host
  if (!line) throw std::runtime_error(what + " printed nothing; log:\n" + process.Log());
  return nlohmann::json::parse(*line);
}

Endpoint StartEmulator(const fs::path& dir, int port, double rate_hz, const std::vector<std::string>& extra) {
  std::vector<std::string> argv = {MOCAPLABEL_EXE, "ndi-emulator", "--port", std::to_string(port), "--json",
                                   "--rate", std::to_string(rate_hz), "--truth", (dir / "truth.csv").string()};
  argv.insert(argv.end(), extra.begin(), extra.end());
  Endpoint e{std::make_unique<ChildProcess>(argv, std::map<std::string, std::string>{}, dir / "emulator.log")};
  e.port = FirstJsonLine(*e.process, "ndi-emulator")["port"];
  return e;
}

Endpoint StartDaemon(const fs::path& rig, const std::map<std::string, std::string>& env, const std::vector<std::string>& args) {
  std::vector<std::string> argv = {MOCAPLABEL_EXE, "capture", "daemon", "--rig", rig.string(), "--json"};
  argv.insert(argv.end(), args.begin(), args.end());
  Endpoint d{std::make_unique<ChildProcess>(argv, env, rig.parent_path() / "daemon.log")};
  d.port = FirstJsonLine(*d.process, "capture daemon")["port"];
  return d;
}

std::pair<int, nlohmann::json> Cli(const fs::path& dir, std::vector<std::string> args) {
  args.insert(args.begin(), MOCAPLABEL_EXE);
  args.push_back("--json");
  ChildProcess cli(args, {}, dir / "cli.log");
  std::string out;  // the whole of stdout: one JSON document, possibly over several lines
  while (const std::optional<std::string> line = cli.ReadLine(30000)) out += *line + "\n";
  const std::optional<int> status = cli.Wait(30000);
  return {status.value_or(-1), nlohmann::json::parse(out, nullptr, false)};
}

nlohmann::json Status(const fs::path& dir, int port) {
  return Cli(dir, {"capture", "status", "--port", std::to_string(port)}).second;
}

nlohmann::json Source(const nlohmann::json& status, const std::string& name) {
  if (!status.is_object() || !status.contains("sources")) return nlohmann::json::object();  // a failed poll
  for (const auto& s : status["sources"])
    if (s["name"] == name) return s["device"];
  return nlohmann::json::object();
}

}  // namespace mocap::testing
