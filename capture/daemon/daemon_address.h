#pragma once
// Where a running capture daemon listens, for clients that know only its rig file (a rig whose
// `control.port` is 0 lets the daemon pick a free port). The daemon writes
// `<sessions_dir>/.capture-daemon.json` once it listens and removes it when it exits; a file left by a
// killed daemon is recognised by its process id and ignored.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace mocap::capture {

struct DaemonAddress {
  std::string bind;  ///< the control address as bound ("0.0.0.0": any)
  int port = 0;      ///< the port actually listened on
  int64_t pid = 0;   ///< the daemon's process
};

/// `<sessions_dir>/.capture-daemon.json` (a dot-file: no session name starts with '.').
std::filesystem::path DaemonAddressFile(const std::filesystem::path& sessions_dir);

/// Writes the file atomically (a temporary file renamed into place). Throws InputError naming the file.
void WriteDaemonAddress(const std::filesystem::path& sessions_dir, const DaemonAddress& address);

/// Removes the file if it still names process `pid` (another daemon may have replaced it).
void RemoveDaemonAddress(const std::filesystem::path& sessions_dir, int64_t pid);

/// The address of a running daemon; nullopt when there is no file or its process is gone. Throws
/// InputError naming the file when it is not a daemon address.
std::optional<DaemonAddress> ReadDaemonAddress(const std::filesystem::path& sessions_dir);

}  // namespace mocap::capture
