#pragma once
// Content hashes of run inputs: XXH3-128 (xxHash 0.8), written as 32 lowercase hex digits. XXH3 is not
// cryptographic; it detects changed inputs, not tampering, and reads at memory speed so hashing a
// session costs about what reading it from disk costs.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mocap::pipeline {

/// XXH3-128 of the file's bytes, 32 lowercase hex digits (the canonical, big-endian form). Streams the
/// file in 1 MiB blocks. InputError naming the file when it cannot be opened or read.
std::string HashFileXxh3(const std::filesystem::path& file);

/// XXH3-128 of a byte string, in the same form as HashFileXxh3.
std::string HashBytesXxh3(std::string_view bytes);

/// What stat(2) says about a file: enough to tell, without reading it, that a file is unchanged.
struct FileStat {
  uint64_t size_bytes = 0;
  int64_t mtime_ns = 0;
  uint64_t inode = 0;
};

/// Stat of a regular file (symbolic links followed); nullopt when missing or not a regular file.
std::optional<FileStat> StatFile(const std::filesystem::path& file);

/// A file modified this recently may be rewritten with the same size within the same (coarse,
/// timer-tick granular) mtime, so its size and mtime cannot vouch for its content yet: such a file is
/// neither cached nor given a stat fast path in run.json (git's "racy clean" rule).
inline constexpr int64_t kRacyWindowNs = 2'000'000'000;

/// True when the file's mtime lies within kRacyWindowNs of now (or in the future).
bool RecentlyModified(const FileStat& stat);

/// One file of a folder input: its path relative to the folder ('/'-separated) and its content hash.
struct TreeEntry {
  std::string relative_path;
  std::string hash;
};

/// Digest of a folder: XXH3-128 over the (relative path, '\0', file hash, '\n') lines sorted by
/// relative path, so the digest does not depend on the order the directory was listed in.
std::string TreeDigest(std::vector<TreeEntry> entries);

}  // namespace mocap::pipeline
