// Fingerprinting a run's inputs and checking them again later (FingerprintInputs, CheckStale).
#include <algorithm>
#include <chrono>
#include <set>

#include "core/check.h"
#include "pipeline/provenance.h"

namespace mocap::pipeline {
namespace fs = std::filesystem;
namespace {

// Absolute, lexically normal, without a trailing separator; symbolic links are kept as given.
fs::path NormalPath(const fs::path& path) {
  fs::path normal = fs::absolute(path).lexically_normal();
  if (!normal.has_filename() && normal.has_parent_path() && normal != normal.root_path()) {
    normal = normal.parent_path();
  }
  return normal;
}

// The message of an InputError without its "where: " prefix.
std::string WhatOnly(const InputError& error) {
  const std::string what = error.what();
  return error.where().empty() ? what : what.substr(error.where().size() + 2);
}

struct TreeFile {
  std::string relative_path;  // '/'-separated, relative to the tree's root
  fs::path path;
  FileStat stat;
};

// Appends every regular file at or under `start` (the root, or a member that is a file or a folder).
void ListMember(const fs::path& root, const fs::path& start, std::vector<TreeFile>* files) {
  if (const std::optional<FileStat> stat = StatFile(start)) {
    files->push_back({start.lexically_relative(root).generic_string(), start, *stat});
    return;
  }
  std::error_code error;
  if (!fs::is_directory(start, error)) throw InputError(start.string(), "missing");
  for (fs::recursive_directory_iterator it(start, error), end; it != end; it.increment(error)) {
    if (error) break;
    if (const std::optional<FileStat> stat = StatFile(it->path())) {
      files->push_back({it->path().lexically_relative(root).generic_string(), it->path(), *stat});
    }
  }
  if (error) throw InputError(start.string(), "cannot list the folder: " + error.message());
}

// The tree's files sorted by relative path, each once. InputError naming what is missing.
std::vector<TreeFile> ListTree(const fs::path& root, const std::vector<std::string>& members) {
  std::error_code error;
  if (!fs::is_directory(root, error)) throw InputError(root.string(), "missing or not a folder");
  std::vector<TreeFile> files;
  if (members.empty()) ListMember(root, root, &files);
  for (const std::string& member : members) {
    const fs::path relative = fs::path(member).lexically_normal();
    if (relative.is_absolute() || relative.empty() || *relative.begin() == "..") {
      throw InputError(member, "a tree member must be a path inside the tree");
    }
    ListMember(root, root / relative, &files);
  }
  std::sort(files.begin(), files.end(),
            [](const TreeFile& a, const TreeFile& b) { return a.relative_path < b.relative_path; });
  files.erase(std::unique(files.begin(), files.end(),
                          [](const TreeFile& a, const TreeFile& b) {
                            return a.relative_path == b.relative_path;
                          }),
              files.end());
  return files;
}

// Size and mtime of every file of a tree as one digest: equal digests mean an untouched tree.
std::string StatDigest(const std::vector<TreeFile>& files) {
  std::vector<TreeEntry> entries;
  entries.reserve(files.size());
  for (const TreeFile& file : files) {
    entries.push_back({file.relative_path, Str(file.stat.size_bytes, ' ', file.stat.mtime_ns)});
  }
  return TreeDigest(std::move(entries));
}

std::string ContentDigest(const std::vector<TreeFile>& files, HashCache& cache) {
  std::vector<TreeEntry> entries;
  entries.reserve(files.size());
  for (const TreeFile& file : files) entries.push_back({file.relative_path, cache.Hash(file.path, file.stat)});
  return TreeDigest(std::move(entries));
}

InputRecord FingerprintTree(const InputSpec& spec, HashCache& cache) {
  const fs::path root = NormalPath(spec.path);
  InputRecord record;
  record.role = spec.role;
  record.path = root.string();
  record.tree = true;
  record.members = spec.members;
  const std::vector<TreeFile> files = ListTree(root, spec.members);
  record.files = static_cast<int64_t>(files.size());
  for (const TreeFile& file : files) record.size_bytes += file.stat.size_bytes;
  record.mtime_ns = 0;
  record.hash = ContentDigest(files, cache);
  // A recently modified file cannot be vouched for by its stat: the tree is then always hashed.
  const bool racy = std::any_of(files.begin(), files.end(),
                                [](const TreeFile& file) { return RecentlyModified(file.stat); });
  record.stat_digest = racy ? "" : StatDigest(files);
  return record;
}

InputRecord FingerprintFile(const InputSpec& spec, HashCache& cache) {
  const fs::path path = NormalPath(spec.path);
  const std::optional<FileStat> stat = StatFile(path);
  if (!stat) throw InputError(path.string(), "missing or not a regular file");
  InputRecord record;
  record.role = spec.role;
  record.path = path.string();
  record.size_bytes = stat->size_bytes;
  // 0 (never equal to a real mtime) for a recently modified file, whose stat cannot vouch for it.
  record.mtime_ns = RecentlyModified(*stat) ? 0 : stat->mtime_ns;
  record.files = 1;
  record.hash = cache.Hash(path, *stat);
  return record;
}


// "" when the file at `path` still has the recorded content, else what changed. `given` is true when
// the path was overridden with a different one, so the recorded size and mtime say nothing about it.
std::string CheckFile(const InputRecord& record, const fs::path& path, bool given, HashCache& cache,
                      StaleReport* report) {
  const std::optional<FileStat> stat = StatFile(path);
  if (!stat) return fs::exists(path) ? "not a regular file" : "missing";
  ++report->files_checked;
  const bool same_stat = record.mtime_ns != 0 && stat->size_bytes == record.size_bytes &&
                         stat->mtime_ns == record.mtime_ns;
  if (!given && same_stat) return "";
  if (cache.Hash(path, *stat) == record.hash) return "";
  return given ? "different file given (content changed)" : "content changed";
}

std::string CheckTree(const InputRecord& record, const fs::path& root, bool given, HashCache& cache,
                      StaleReport* report) {
  std::error_code error;
  if (!fs::exists(root, error)) return "missing";
  std::vector<TreeFile> files;
  try {
    files = ListTree(root, record.members);
  } catch (const InputError& e) {
    return e.where() == root.string() ? WhatOnly(e) : Str(WhatOnly(e), ": ", e.where());
  }
  report->files_checked += static_cast<int64_t>(files.size());
  if (!given && !record.stat_digest.empty() && StatDigest(files) == record.stat_digest) return "";
  if (ContentDigest(files, cache) == record.hash) return "";
  return given ? "different folder given (content changed)" : "content changed";
}

}  // namespace

std::vector<InputRecord> FingerprintInputs(const std::vector<InputSpec>& inputs, HashCache& cache) {
  std::vector<InputRecord> records;
  std::set<std::string> roles;
  for (const InputSpec& spec : inputs) {
    if (!roles.insert(spec.role).second) {
      throw InputError(spec.path.string(), "input role '" + spec.role + "' is given twice");
    }
    try {
      records.push_back(spec.tree ? FingerprintTree(spec, cache) : FingerprintFile(spec, cache));
    } catch (const InputError& e) {
      throw InputError(e.where(), Str(spec.role, " input: ", WhatOnly(e)));
    }
  }
  return records;
}

StaleReport CheckStale(const RunProvenance& run, const std::map<std::string, fs::path>& overrides,
                       HashCache& cache) {
  const auto start = std::chrono::steady_clock::now();
  const int64_t hashed_before = cache.files_hashed();
  StaleReport report;
  std::set<std::string> recorded_roles;
  for (const InputRecord& record : run.inputs) {
    recorded_roles.insert(record.role);
    fs::path path = record.path;
    bool given = false;
    if (auto it = overrides.find(record.role); it != overrides.end()) {
      path = NormalPath(it->second);
      given = path.string() != record.path;
    }
    const std::string what = record.tree ? CheckTree(record, path, given, cache, &report)
                                         : CheckFile(record, path, given, cache, &report);
    if (!what.empty()) report.changes.push_back({record.role, path.string(), what});
  }
  for (const auto& [role, path] : overrides) {
    if (!recorded_roles.count(role)) {
      report.changes.push_back({role, NormalPath(path).string(), "not recorded in the run"});
    }
  }
  report.stale = !report.changes.empty();
  report.files_hashed = cache.files_hashed() - hashed_before;
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

nlohmann::json ToJson(const StaleReport& report) {
  nlohmann::json changes = nlohmann::json::array();
  for (const InputChange& change : report.changes) {
    changes.push_back({{"role", change.role}, {"path", change.path}, {"what", change.what}});
  }
  return {{"stale", report.stale},
          {"changes", std::move(changes)},
          {"files_checked", report.files_checked},
          {"files_hashed", report.files_hashed},
          {"seconds", report.seconds}};
}

}  // namespace mocap::pipeline
