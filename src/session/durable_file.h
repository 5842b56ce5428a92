#pragma once
// POSIX file primitives with the durability the session format promises. Every failure throws
// InputError naming the file and the system error (e.g. "No space left on device").
#include <atomic>
#include <filesystem>
#include <string>
#include <string_view>

namespace mocap {

/// Writes `contents` to `path` atomically: a temporary sibling, fdatasync, rename over `path`, fsync of
/// the folder. Readers see the old or the new file, never a mixture.
void WriteFileAtomically(const std::filesystem::path& path, std::string_view contents);

/// Writes `contents` to `path` (created or truncated), optionally fdatasync'd. On failure the partial
/// file is removed before the exception leaves.
void WriteFileRemovingOnFailure(const std::filesystem::path& path, std::string_view contents, bool sync);

/// Places an already-encoded file at `path`: a hard link where the file system allows one, else a byte
/// copy written with our own writes (std::filesystem::copy_file reports a sendfile that ran out of space
/// as EIO, and the user needs the real reason); never a re-encode. Through a temporary sibling and a
/// rename, so `path` is whole or absent. Returns true when linked.
bool LinkOrCopyFile(const std::filesystem::path& source, const std::filesystem::path& path);

/// fsync of a folder, so that renames and new entries in it are durable.
void SyncDirectory(const std::filesystem::path& dir);

/// An append-only file descriptor (O_APPEND). Appends must be serialised by the caller; Sync() may run
/// concurrently with them (from a syncing thread).
class AppendFile {
 public:
  /// Opens (creating) `path` for appending.
  explicit AppendFile(const std::filesystem::path& path);
  ~AppendFile();
  AppendFile(const AppendFile&) = delete;
  AppendFile& operator=(const AppendFile&) = delete;

  /// Appends all bytes (retrying short writes). Throws InputError naming the file on failure; the file
  /// may then end in a partial line, which readers detect and ignore.
  void Append(std::string_view bytes);
  /// fdatasync when something was appended since the last sync (an append racing with it is synced by
  /// the next call).
  void Sync();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int fd_ = -1;
  std::atomic<bool> dirty_ = false;
};

}  // namespace mocap
