#include "capture/daemon/daemon_address.h"

#include <signal.h>

#include <cerrno>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/check.h"

namespace mocap::capture {
namespace {

namespace fs = std::filesystem;

bool ProcessRuns(int64_t pid) {
  if (pid <= 0) return false;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;  // EPERM: runs, as another user
}

std::optional<DaemonAddress> Parse(const fs::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;  // removed meanwhile
  std::stringstream text;
  text << in.rdbuf();
  const nlohmann::json j = nlohmann::json::parse(text.str(), nullptr, false);
  const bool ok = j.is_object() && j.contains("bind") && j["bind"].is_string() && j.contains("port") &&
                  j["port"].is_number_integer() && j.contains("pid") && j["pid"].is_number_integer();
  if (!ok) throw InputError(file.string(), "is not a capture daemon address {\"bind\", \"port\", \"pid\"}: remove it");
  return DaemonAddress{j["bind"].get<std::string>(), j["port"].get<int>(), j["pid"].get<int64_t>()};
}

}  // namespace

fs::path DaemonAddressFile(const fs::path& sessions_dir) { return sessions_dir / ".capture-daemon.json"; }

void WriteDaemonAddress(const fs::path& sessions_dir, const DaemonAddress& address) {
  const fs::path file = DaemonAddressFile(sessions_dir);
  const fs::path temporary = file.string() + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << nlohmann::json{{"bind", address.bind}, {"port", address.port}, {"pid", address.pid}}.dump() << "\n";
    if (!out.flush()) throw InputError(temporary.string(), "cannot write the daemon's address");
  }
  std::error_code error;
  fs::rename(temporary, file, error);
  if (error) throw InputError(file.string(), "cannot write the daemon's address: " + error.message());
}

void RemoveDaemonAddress(const fs::path& sessions_dir, int64_t pid) {
  try {
    const std::optional<DaemonAddress> address = Parse(DaemonAddressFile(sessions_dir));
    if (!address || address->pid != pid) return;
  } catch (const InputError&) {
    return;  // not ours to remove
  }
  std::error_code ignored;
  fs::remove(DaemonAddressFile(sessions_dir), ignored);
}

std::optional<DaemonAddress> ReadDaemonAddress(const fs::path& sessions_dir) {
  const fs::path file = DaemonAddressFile(sessions_dir);
  if (!fs::exists(file)) return std::nullopt;
  std::optional<DaemonAddress> address = Parse(file);
  if (address && !ProcessRuns(address->pid)) return std::nullopt;  // left by a killed daemon
  return address;
}

}  // namespace mocap::capture
