#include "pipeline/hash_cache.h"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <random>

#include "core/check.h"

namespace mocap::pipeline {
namespace fs = std::filesystem;
namespace {

constexpr const char* kHeader = "# mocaplabel hash cache v1: xxh3-128 size_bytes mtime_ns inode path";

std::string Key(const fs::path& file) { return fs::absolute(file).lexically_normal().string(); }

bool SameStat(const FileStat& a, const FileStat& b) {
  return a.size_bytes == b.size_bytes && a.mtime_ns == b.mtime_ns && a.inode == b.inode;
}

// One line: hash \t size \t mtime_ns \t inode \t path (last, so a path may hold tabs). Bad lines -> false.
bool ParseLine(const std::string& line, std::string* path, FileStat* stat, std::string* hash) {
  size_t tabs[4];
  size_t from = 0;
  for (size_t& tab : tabs) {
    tab = line.find('\t', from);
    if (tab == std::string::npos) return false;
    from = tab + 1;
  }
  *hash = line.substr(0, tabs[0]);
  if (hash->size() != 32 || hash->find_first_not_of("0123456789abcdef") != std::string::npos) return false;
  try {
    stat->size_bytes = std::stoull(line.substr(tabs[0] + 1, tabs[1] - tabs[0] - 1));
    stat->mtime_ns = std::stoll(line.substr(tabs[1] + 1, tabs[2] - tabs[1] - 1));
    stat->inode = std::stoull(line.substr(tabs[2] + 1, tabs[3] - tabs[2] - 1));
  } catch (const std::exception&) {
    return false;
  }
  *path = line.substr(tabs[3] + 1);
  return !path->empty();
}

template <typename Map>
Map LoadCacheFile(const fs::path& file) {
  Map entries;
  std::ifstream in(file);
  std::string line;
  if (!in || !std::getline(in, line) || line != kHeader) return entries;  // none, or another format
  std::string path, hash;
  FileStat stat;
  while (std::getline(in, line)) {
    if (ParseLine(line, &path, &stat, &hash)) entries[path] = {stat, hash};
  }
  return entries;
}

std::string TempSuffix() {
  std::random_device random;
  return ".tmp." + std::to_string(::getpid()) + "." + std::to_string(random());
}

// Temp file + rename: a concurrent reader sees the old file or the new one, never a torn one.
void WriteAtomically(const fs::path& file, const std::string& text) {
  std::error_code error;
  fs::create_directories(file.parent_path(), error);
  const fs::path temp = file.string() + TempSuffix();
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out << text;
    out.flush();
    if (!out) {
      fs::remove(temp, error);
      throw InputError(temp.string(), "cannot write the hash cache");
    }
  }
  fs::rename(temp, file, error);
  if (error) {
    const std::string message = error.message();
    fs::remove(temp, error);
    throw InputError(file.string(), "cannot replace the hash cache: " + message);
  }
}

}  // namespace

fs::path DefaultHashCacheDir() {
  if (const char* dir = std::getenv("MOCAPLABEL_CACHE_DIR"); dir && *dir) return fs::path(dir);
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "mocaplabel";
  if (const char* home = std::getenv("HOME"); home && *home) {
    return fs::path(home) / ".cache" / "mocaplabel";
  }
  return {};
}

fs::path HashCacheFile(const fs::path& cache_dir) { return cache_dir / "hashes.tsv"; }

HashCache::HashCache(fs::path cache_dir) : cache_dir_(std::move(cache_dir)) {
  if (!cache_dir_.empty()) entries_ = LoadCacheFile<EntryMap>(HashCacheFile(cache_dir_));
}

HashCache::~HashCache() {
  try {
    Save();
  } catch (...) {
    // Only a cache: the next run hashes these files again.
  }
}

std::string HashCache::Hash(const fs::path& file, const FileStat& stat) {
  std::string key = Key(file);
  if (auto it = entries_.find(key); it != entries_.end() && SameStat(it->second.stat, stat)) {
    return it->second.hash;
  }
  std::string hash = HashFileXxh3(file);
  ++files_hashed_;
  bytes_hashed_ += stat.size_bytes;
  // A recently modified file could change again without its stat changing: hashed, but not cached.
  if (!RecentlyModified(stat)) {
    entries_[key] = {stat, hash};
    added_[key] = {stat, hash};
  }
  return hash;
}

void HashCache::Save() {
  if (cache_dir_.empty() || added_.empty()) return;
  // Merge over what other processes saved since we loaded; keep only entries that still describe
  // their file, which bounds the cache by the files in use.
  EntryMap merged = LoadCacheFile<EntryMap>(HashCacheFile(cache_dir_));
  for (auto& [path, entry] : added_) merged[path] = entry;
  for (auto it = merged.begin(); it != merged.end();) {
    const std::optional<FileStat> now = StatFile(it->first);
    it = (now && SameStat(*now, it->second.stat)) ? std::next(it) : merged.erase(it);
  }
  std::string text = std::string(kHeader) + '\n';
  for (const auto& [path, entry] : merged) {
    if (path.find('\n') != std::string::npos) continue;  // cannot be stored line-wise
    text += Str(entry.hash, '\t', entry.stat.size_bytes, '\t', entry.stat.mtime_ns, '\t',
                entry.stat.inode, '\t', path, '\n');
  }
  WriteAtomically(HashCacheFile(cache_dir_), text);
  entries_ = std::move(merged);
  added_.clear();
}

}  // namespace mocap::pipeline
