#pragma once
// A persistent cache of content hashes keyed by (absolute path, size, mtime_ns, inode), so checking a
// run against thousands of unchanged input files costs one stat per file, not a read. It is only a
// cache: a missing, unreadable or corrupt cache file means files are hashed again, never an error.
#include <cstdint>
#include <filesystem>
#include <string>
#include <unordered_map>

#include "pipeline/content_hash.h"

namespace mocap::pipeline {

/// Where the hash cache lives: $MOCAPLABEL_CACHE_DIR, else $XDG_CACHE_HOME/mocaplabel, else
/// $HOME/.cache/mocaplabel; "" when none of them is set (the cache is then kept in memory only).
std::filesystem::path DefaultHashCacheDir();

/// The cache file inside a cache folder.
std::filesystem::path HashCacheFile(const std::filesystem::path& cache_dir);

class HashCache {
 public:
  /// Loads `cache_dir`/hashes.tsv when there is one. An empty cache_dir keeps the cache in memory.
  explicit HashCache(std::filesystem::path cache_dir = DefaultHashCacheDir());
  /// Saves when something was added; never throws (a cache that cannot be written is not kept).
  ~HashCache();
  HashCache(const HashCache&) = delete;
  HashCache& operator=(const HashCache&) = delete;

  /// Hash of a file, from the cache when path+size+mtime+inode match, else read and hashed.
  /// `stat` is the file's current StatFile (the caller has it already).
  std::string Hash(const std::filesystem::path& file, const FileStat& stat);

  /// Writes the cache file (temp file + rename, so concurrent processes never see a torn file; the
  /// last writer wins, after merging what other processes saved in the meantime). Entries of files
  /// that are gone or changed are dropped, which keeps the file bounded by the files in use.
  /// Throws InputError when the folder or file cannot be written.
  void Save();

  const std::filesystem::path& cache_dir() const { return cache_dir_; }
  int64_t files_hashed() const { return files_hashed_; }  ///< files read by this object
  uint64_t bytes_hashed() const { return bytes_hashed_; }  ///< bytes read by this object
  size_t entries() const { return entries_.size(); }

 private:
  struct Entry {
    FileStat stat;
    std::string hash;
  };
  using EntryMap = std::unordered_map<std::string, Entry>;

  std::filesystem::path cache_dir_;
  EntryMap entries_;  // key: absolute, lexically normal path
  EntryMap added_;    // entries this object hashed, merged over the file on disk when saving
  int64_t files_hashed_ = 0;
  uint64_t bytes_hashed_ = 0;
};

}  // namespace mocap::pipeline
