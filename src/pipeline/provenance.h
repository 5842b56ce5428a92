#pragma once
// Provenance of a run directory (docs/provenance.md): every run the tool writes (label run, validation
// run, demo) holds run.json with the command, the tool's version and commit, the options and a content
// hash of every input, so that a run can tell cheaply whether it is stale against its inputs.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/hash_cache.h"

namespace mocap::pipeline {

/// Version of the run.json layout; a reader refuses files of a newer layout.
inline constexpr int kRunJsonFormatVersion = 1;

/// One input of a run, as recorded in run.json.
struct InputRecord {
  std::string role;  ///< "session", "rig", "objects", "mesh:<object name>", "labels", ...
  std::string path;  ///< absolute, as given (symbolic links not resolved)
  bool tree = false;  ///< a folder: `members` hashed as one digest
  /// Tree only: relative paths of files/folders under `path`; empty = every regular file under it.
  std::vector<std::string> members;
  uint64_t size_bytes = 0;  ///< file size, or sum over the tree's files
  /// File only (0 for trees, and for a file modified within kRacyWindowNs of being fingerprinted,
  /// which is then always hashed when checked).
  int64_t mtime_ns = 0;
  int64_t files = 1;        ///< 1 for a file, file count for a tree
  /// File: HashFileXxh3; tree: TreeDigest over its files (relative path, file hash).
  std::string hash;
  /// Tree only: XXH3-128 over the sorted (relative path, size, mtime_ns) lines, so an untouched
  /// tree is recognised by stat alone even without the hash cache ("" for files, and for a tree with
  /// a file modified within kRacyWindowNs of being fingerprinted).
  std::string stat_digest;
};

/// An input to fingerprint. `members` only for trees (relative files/folders; empty = all files).
struct InputSpec {
  std::string role;
  std::filesystem::path path;
  bool tree = false;
  std::vector<std::string> members;
};

/// Fingerprints each input (through the cache). A missing input is an InputError naming it and its
/// role; so is a role given twice (overrides address inputs by role).
std::vector<InputRecord> FingerprintInputs(const std::vector<InputSpec>& inputs, HashCache& cache);

struct RunProvenance {
  std::string kind;                  ///< "label", "validation", "demo", ...
  std::vector<std::string> command;  ///< argv as run
  std::string tool_version, git_commit;
  bool git_dirty = false;
  std::string created_utc;  ///< ISO 8601, e.g. 2026-12-02T10:00:00Z
  nlohmann::json options = nlohmann::json::object();
  std::vector<InputRecord> inputs;
  nlohmann::json shard;  ///< null, or {"index", "count", "begin", "end"} for a shard's run
};

/// A provenance with version, commit, dirty flag and created_utc (now) filled in.
RunProvenance NewProvenance(std::string kind, std::vector<std::string> command, nlohmann::json options);

nlohmann::json ToJson(const InputRecord& input);
nlohmann::json ToJson(const RunProvenance& run);
/// Strict: a missing, mistyped or unknown field is an InputError(where, ...) naming the field.
RunProvenance ProvenanceFromJson(const nlohmann::json& json, const std::string& where);

/// Writes run_dir/run.json through a temp file and a rename; InputError on failure.
void WriteRunJson(const std::filesystem::path& run_dir, const RunProvenance& run);
/// Reads run_dir/run.json; InputError "<dir>/run.json: ..." when it is missing or malformed.
RunProvenance ReadRunJson(const std::filesystem::path& run_dir);
/// The file `run` recorded for `role` ("rig", "objects"; empty when none).
std::filesystem::path RecordedInput(const RunProvenance& run, const std::string& role);

struct InputChange {
  std::string role, path;
  /// "content changed", "missing", "different file given (content changed)", "not recorded in the
  /// run", ...
  std::string what;
};

struct StaleReport {
  bool stale = false;
  std::vector<InputChange> changes;
  int64_t files_checked = 0;  ///< files stat'ed
  int64_t files_hashed = 0;   ///< files read (neither size+mtime nor the cache could vouch for them)
  double seconds = 0;
};

/// Compares the run's recorded inputs with their current state. `overrides` (role -> path) replaces a
/// recorded input's path (e.g. `info RUN --rig new.yaml`); a role in overrides the run did not record
/// is reported as a change. Files whose size and mtime equal the recorded ones (trees: whose
/// stat_digest is unchanged) are taken as unchanged without reading them; others are hashed through the
/// cache, so touching a file without changing its bytes does not make the run stale, while changing
/// one byte does.
StaleReport CheckStale(const RunProvenance& run,
                       const std::map<std::string, std::filesystem::path>& overrides, HashCache& cache);

nlohmann::json ToJson(const StaleReport& report);

}  // namespace mocap::pipeline
