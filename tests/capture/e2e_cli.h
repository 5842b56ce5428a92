#pragma once
// `mocaplabel` as separate processes for the capture end-to-end tests: the NDI emulator, the capture
// daemon and the client commands, each answering with the JSON it prints. Test support only.
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "process.h"

namespace mocap::testing {

struct Endpoint {
  std::unique_ptr<ChildProcess> process;
  int port = 0;
};

/// The first stdout line of `process` as JSON (where it listens); throws with its log when none comes.
nlohmann::json FirstJsonLine(ChildProcess& process, const std::string& what);

/// `mocaplabel ndi-emulator --port PORT --json --rate RATE --truth DIR/truth.csv EXTRA...`.
Endpoint StartEmulator(const std::filesystem::path& dir, int port, double rate_hz, const std::vector<std::string>& extra = {});

/// `mocaplabel capture daemon --rig RIG --json ARGS...` (log: the rig's folder/daemon.log).
Endpoint StartDaemon(const std::filesystem::path& rig, const std::map<std::string, std::string>& env,
                     const std::vector<std::string>& args = {"--port", "0"});

/// Runs `mocaplabel ARGS... --json`; its exit status and the JSON document it printed (discarded if none).
std::pair<int, nlohmann::json> Cli(const std::filesystem::path& dir, std::vector<std::string> args);

/// `capture status --port PORT`.
nlohmann::json Status(const std::filesystem::path& dir, int port);

/// The `device` counters of source `name` in a status document (empty for a failed poll).
nlohmann::json Source(const nlohmann::json& status, const std::string& name);

}  // namespace mocap::testing
