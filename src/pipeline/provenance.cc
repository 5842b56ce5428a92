// run.json: building, writing and strictly reading a run's provenance.
#include "pipeline/provenance.h"

#include <unistd.h>

#include <ctime>
#include <fstream>
#include <set>

#include "core/check.h"
#include "core/utc_time.h"
#include "pipeline/build_info.h"

namespace mocap::pipeline {
namespace fs = std::filesystem;
using nlohmann::json;
namespace {

// Strict field access on one JSON object of run.json; errors name the field by its full path.
class Fields {
 public:
  Fields(const json& object, const std::string& where, std::string prefix)
      : object_(object), where_(where), prefix_(std::move(prefix)) {
    if (!object_.is_object()) Fail(prefix_.empty() ? "the file" : prefix_, "must be an object");
  }
  // Throws when the object holds a field not in `known` (a misspelt field must not pass unnoticed).
  void OnlyThese(std::initializer_list<const char*> known) const {
    const std::set<std::string> names(known.begin(), known.end());
    for (const auto& [key, value] : object_.items()) {
      if (!names.count(key)) Fail(Name(key), "is not a run.json field (misspelt?)");
    }
  }
  const json& Get(const std::string& key, bool (json::*is_type)() const noexcept,
                  const char* type) const {
    const auto it = object_.find(key);
    if (it == object_.end()) Fail(Name(key), "is missing");
    if (!((*it).*is_type)()) Fail(Name(key), Str("must be ", type, ", not ", it->type_name()));
    return *it;
  }
  std::string String(const std::string& key) const {
    return Get(key, &json::is_string, "a string").get<std::string>();
  }
  bool Bool(const std::string& key) const { return Get(key, &json::is_boolean, "true or false").get<bool>(); }
  int64_t Int(const std::string& key) const {
    return Get(key, &json::is_number_integer, "an integer").get<int64_t>();
  }
  uint64_t Unsigned(const std::string& key) const {
    return Get(key, &json::is_number_unsigned, "a non-negative integer").get<uint64_t>();
  }
  std::vector<std::string> Strings(const std::string& key) const {
    std::vector<std::string> out;
    for (const json& item : Get(key, &json::is_array, "an array of strings")) {
      if (!item.is_string()) Fail(Name(key), "must be an array of strings");
      out.push_back(item.get<std::string>());
    }
    return out;
  }
  std::string Name(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  [[noreturn]] void Fail(const std::string& field, const std::string& what) const {
    throw InputError(where_, Str("field '", field, "' ", what));
  }

 private:
  const json& object_;
  const std::string& where_;
  std::string prefix_;
};

InputRecord InputFromJson(const json& object, const std::string& where, const std::string& prefix) {
  const Fields fields(object, where, prefix);
  fields.OnlyThese({"role", "path", "tree", "members", "size_bytes", "mtime_ns", "files", "hash",
                    "stat_digest"});
  InputRecord input;
  input.role = fields.String("role");
  input.path = fields.String("path");
  input.tree = fields.Bool("tree");
  input.members = fields.Strings("members");
  input.size_bytes = fields.Unsigned("size_bytes");
  input.mtime_ns = fields.Int("mtime_ns");
  input.files = fields.Int("files");
  input.hash = fields.String("hash");
  input.stat_digest = fields.String("stat_digest");
  if (input.files < 0) fields.Fail(fields.Name("files"), "must not be negative");
  return input;
}

json ShardFromJson(const json& shard, const std::string& where) {
  if (shard.is_null()) return shard;
  const Fields fields(shard, where, "shard");
  fields.OnlyThese({"index", "count", "begin", "end"});
  for (const char* key : {"index", "count", "begin", "end"}) fields.Int(key);
  return shard;
}

}  // namespace

RunProvenance NewProvenance(std::string kind, std::vector<std::string> command, json options) {
  const BuildInfo& build = CurrentBuildInfo();
  RunProvenance run;
  run.kind = std::move(kind);
  run.command = std::move(command);
  run.tool_version = build.version;
  run.git_commit = build.git_commit;
  run.git_dirty = build.git_dirty;
  run.created_utc = NowUtcIso8601();
  run.options = std::move(options);
  return run;
}

json ToJson(const InputRecord& input) {
  return {{"role", input.role},         {"path", input.path},         {"tree", input.tree},
          {"members", input.members},   {"size_bytes", input.size_bytes},
          {"mtime_ns", input.mtime_ns}, {"files", input.files},       {"hash", input.hash},
          {"stat_digest", input.stat_digest}};
}

json ToJson(const RunProvenance& run) {
  json inputs = json::array();
  for (const InputRecord& input : run.inputs) inputs.push_back(ToJson(input));
  return {{"format_version", kRunJsonFormatVersion},
          {"kind", run.kind},
          {"command", run.command},
          {"tool_version", run.tool_version},
          {"git_commit", run.git_commit},
          {"git_dirty", run.git_dirty},
          {"created_utc", run.created_utc},
          {"options", run.options},
          {"inputs", std::move(inputs)},
          {"shard", run.shard}};
}

RunProvenance ProvenanceFromJson(const json& json_run, const std::string& where) {
  const Fields fields(json_run, where, "");
  fields.OnlyThese({"format_version", "kind", "command", "tool_version", "git_commit", "git_dirty",
                    "created_utc", "options", "inputs", "shard"});
  const int64_t format = fields.Int("format_version");
  if (format > kRunJsonFormatVersion) {
    fields.Fail("format_version", Str("is ", format, ": written by a newer mocaplabel, update the tool"));
  }
  RunProvenance run;
  run.kind = fields.String("kind");
  run.command = fields.Strings("command");
  run.tool_version = fields.String("tool_version");
  run.git_commit = fields.String("git_commit");
  run.git_dirty = fields.Bool("git_dirty");
  run.created_utc = fields.String("created_utc");
  run.options = fields.Get("options", &json::is_object, "an object");
  const json& inputs = fields.Get("inputs", &json::is_array, "an array");
  for (size_t i = 0; i < inputs.size(); ++i) {
    run.inputs.push_back(InputFromJson(inputs[i], where, Str("inputs[", i, "]")));
  }
  const auto shard = json_run.find("shard");
  if (shard == json_run.end()) fields.Fail("shard", "is missing (null for an unsharded run)");
  run.shard = ShardFromJson(*shard, where);
  return run;
}

void WriteRunJson(const fs::path& run_dir, const RunProvenance& run) {
  const fs::path file = run_dir / "run.json";
  const fs::path temp = run_dir / Str(".run.json.tmp.", ::getpid());
  std::error_code error;
  fs::create_directories(run_dir, error);
  {
    std::ofstream out(temp, std::ios::trunc);
    out << ToJson(run).dump(2) << '\n';
    out.flush();
    if (!out) {
      fs::remove(temp, error);
      throw InputError(file.string(), "cannot write (is the run folder writable?)");
    }
  }
  fs::rename(temp, file, error);
  if (error) {
    const std::string message = error.message();
    fs::remove(temp, error);
    throw InputError(file.string(), "cannot write: " + message);
  }
}

RunProvenance ReadRunJson(const fs::path& run_dir) {
  const fs::path file = run_dir / "run.json";
  std::ifstream in(file);
  if (!in) {
    throw InputError(file.string(), "missing: not a run folder, or a run written before provenance");
  }
  json parsed;
  try {
    parsed = json::parse(in);
  } catch (const json::exception& e) {
    throw InputError(file.string(), Str("not valid JSON: ", e.what()));
  }
  return ProvenanceFromJson(parsed, file.string());
}

fs::path RecordedInput(const RunProvenance& run, const std::string& role) {
  for (const InputRecord& input : run.inputs)
    if (input.role == role) return input.path;
  return {};
}

}  // namespace mocap::pipeline
