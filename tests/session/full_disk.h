#pragma once
// A full disk on demand: a forked child gets its own mount namespace with a 1 MiB tmpfs, where the code
// under test writes until it fails. Test support only.
#include <filesystem>
#include <functional>
#include <string>

namespace mocap::testing {

/// Reports the child's result to the parent and ends the child.
using SayFn = std::function<void(const std::string&)>;

/// Mounts a 1 MiB tmpfs at `mount_point` in a child process and runs `body` there; `body` ends by calling
/// `say` with "OK ..." or "FAIL ...". Returns what it said, "SKIP ..." when this machine does not allow a
/// private tmpfs (no user or mount namespaces), or "FAIL ..." when the child ended without a word.
std::string RunOnFullDiskInChild(const std::filesystem::path& mount_point, const std::function<void(const SayFn&)>& body);

}  // namespace mocap::testing
