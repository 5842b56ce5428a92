#include "pipeline/shards.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "core/check.h"
#include "pipeline/json_read.h"
#include "pipeline/label_run.h"
#include "pipeline/object_library.h"
#include "pipeline/provenance.h"
#include "pipeline/publish.h"
#include "pipeline/session_wide.h"
#include "pipeline/validation_run.h"
#include "validate/report_html.h"
#include "pipeline/yaml_write.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct ShardRun {
  fs::path dir;
  RunProvenance provenance;
  json manifest;
  Shard shard;
};

ShardRun ReadShard(const fs::path& dir, const fs::path& manifest) {
  ShardRun s{dir, ReadRunJson(dir), ReadJsonFile(manifest), {}};
  const JsonFields f(s.provenance.shard, (dir / "run.json").string() + " shard");
  s.shard = {static_cast<int>(f.Integer("index")), static_cast<int>(f.Integer("count")), f.Integer("begin"), f.Integer("end")};
  return s;
}

/// The shards in range order; they must tile [0, end of the last) and have read the same inputs.
void CheckTiling(std::vector<ShardRun>& shards) {
  if (shards.empty()) throw InputError("merge", "no shards to merge");
  std::sort(shards.begin(), shards.end(), [](const ShardRun& a, const ShardRun& b) { return a.shard.begin < b.shard.begin; });
  int64_t next = 0;
  for (const ShardRun& s : shards) {
    if (s.shard.begin != next)
      throw InputError(s.dir.string(), Str("shard starts at frame ", s.shard.begin, ", expected ", next, ": a shard is missing or overlaps"));
    next = s.shard.end;
    if (s.shard.count != static_cast<int>(shards.size()))
      throw InputError(s.dir.string(), Str("shard of ", s.shard.count, ", but ", shards.size(), " shards given"));
    if (s.shard.end < 0 && &s != &shards.back()) throw InputError(s.dir.string(), "a shard open to the end is not the last");
    const json a = ToJson(shards.front().provenance)["inputs"], b = ToJson(s.provenance)["inputs"];
    for (size_t i = 0; i < std::max(a.size(), b.size()); ++i)
      if (i >= a.size() || i >= b.size() || a[i]["role"] != b[i]["role"] || a[i]["hash"] != b[i]["hash"])
        throw InputError(s.dir.string(), "read other inputs than " + shards.front().dir.string() + "; relabel the shards together");
  }
  if (shards.back().shard.end >= 0) throw InputError(shards.back().dir.string(), "the last shard does not reach the session's end");
}

/// The lines of a JSON-lines file by their "camera" field, in file order, as written: a merge copies
/// bytes, so the merged file is the one a single pass writes (a parse and a dump need not be).
std::map<std::string, std::vector<std::string>> LineListsByCamera(const fs::path& file) {
  const auto records = ReadJsonLines(file);  // every line a whole JSON object, or an error naming it
  std::ifstream in(file, std::ios::binary);
  std::map<std::string, std::vector<std::string>> out;
  size_t k = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    const auto& [where, j] = records.at(k++);
    out[JsonFields(j, where).String("camera")].push_back(line + "\n");
  }
  return out;
}
std::map<std::string, std::string> LinesByCamera(const fs::path& file) {
  std::map<std::string, std::string> out;
  for (const auto& [camera, lines] : LineListsByCamera(file))
    for (const std::string& line : lines) out[camera] += line;
  return out;
}

/// The session-wide step over the merged records when the shards were asked for it (run.json options
/// "session_wide"; a shard leaves it to the merge): the lines of the records it flags get their new
/// verdict, every other line stays as the shard wrote it.
void ApplySessionWideStep(const RunProvenance& run, SessionValidation& merged, std::vector<std::string>& lines) {
  if (!run.options.value("session_wide", false)) return;
  const std::vector<ValidationObject> objects = ValidationObjectsOf(ReadObjectLibrary(RecordedInput(run, "objects")));
  for (size_t i : FlagSessionWideErrors(merged, objects, {})) {
    json j = json::parse(lines[i]);
    const LabelCheck& c = merged.records[i].check;
    j["verdict"] = ToString(c.verdict), j["reason_code"] = ToString(c.reason_code), j["reason"] = c.reason;
    lines[i] = j.dump() + "\n";
  }
}

/// Moves every file of `from` (but the run's own files) into `to`, folder by folder.
void MoveFrameFiles(const fs::path& from, const fs::path& to) {
  for (const auto& entry : fs::recursive_directory_iterator(from)) {
    const fs::path relative = fs::relative(entry.path(), from);
    if (entry.is_directory()) {
      fs::create_directories(to / relative);
    } else if (relative.has_parent_path()) {  // top-level files are the run's own
      fs::rename(entry.path(), to / relative);
    }
  }
}

json MergedManifest(const std::vector<ShardRun>& shards, const fs::path& out) {
  json m = shards.front().manifest;
  for (const char* key : {"frames", "frames_skipped", "records", "records_with_pose", "frames_flagged"}) {
    int64_t sum = 0;
    for (const ShardRun& s : shards) sum += s.manifest.at(key).get<int64_t>();
    m[key] = sum;
  }
  json flags = json::object();
  for (const ShardRun& s : shards)
    for (const auto& [flag, n] : s.manifest.at("flag_counts").items()) flags[flag] = flags.value(flag, int64_t{0}) + n.get<int64_t>();
  m["flag_counts"] = flags;
  for (const char* key : {"seconds", "setup_seconds", "frames_seconds", "frames_cpu_seconds", "render_seconds"}) {
    double sum = 0;
    for (const ShardRun& s : shards) sum += s.manifest.at(key).get<double>();
    m[key] = sum;  // summed over shards: the work, not the wall clock of a parallel run
  }
  m["shards"] = shards.size();
  m["out"] = fs::absolute(out).lexically_normal().string();
  return m;
}

void RemoveShards(const std::vector<ShardRun>& shards) {
  for (const ShardRun& s : shards) fs::remove_all(s.dir);
  std::error_code ignored;
  fs::remove(shards.front().dir.parent_path(), ignored);  // <out>.shards, once empty
}

/// validation.jsonl, report.html and validation.json of merged records; the summary's settings (masks,
/// crops, mode, stride, inputs) are the shards'.
void WriteMergedValidation(const SessionValidation& merged, const std::string& jsonl, const json& shard_summary,
                           const fs::path& dir, const fs::path& out) {
  const ValidationRunLayout layout{dir};
  WriteTextAtomically(layout.records_jsonl(), jsonl);
  WriteTextAtomically(layout.report_html(), ValidationReportHtml(merged, VerdictOptions{}, out));
  SessionCheckOptions options;
  options.labels_dir = shard_summary.at("labels").get<std::string>();
  json summary = ValidationSummaryJson(merged.summary, options, shard_summary.at("session").get<std::string>());
  for (const char* key : {"labels", "masks", "mask_values", "crops", "mode", "frame_stride"}) summary[key] = shard_summary.at(key);
  WriteTextAtomically(layout.summary_json(), summary.dump(2) + "\n");
}

}  // namespace

std::vector<Shard> SplitShards(int64_t frames, int count) {
  if (count < 1) throw InputError("shards", "the shard count must be >= 1");
  std::vector<Shard> shards;
  int64_t begin = 0;
  for (int i = 0; i < count; ++i) {
    const int64_t size = frames / count + (i < frames % count ? 1 : 0);
    shards.push_back({i, count, begin, i + 1 == count ? -1 : begin + size});
    begin += size;
  }
  return shards;
}

fs::path ShardDir(const fs::path& out, const Shard& shard) {
  char name[32];
  std::snprintf(name, sizeof name, "%03d-of-%03d", shard.index, shard.count);
  fs::path dir = out;
  dir += ".shards";
  return dir / name;
}

void MergeLabelShards(const std::vector<fs::path>& shard_dirs, const fs::path& out) {
  std::vector<ShardRun> shards;
  for (const fs::path& dir : shard_dirs) shards.push_back(ReadShard(dir, LabelRunLayout{dir}.manifest_json()));
  CheckTiling(shards);
  PartialOutput output(out, "label_manifest.json", "label");
  std::string lines;
  std::vector<std::map<std::string, std::string>> by_camera;
  for (const ShardRun& s : shards) {
    LabelRun::Read(s.dir);  // every record typed and checked
    by_camera.push_back(LinesByCamera(LabelRunLayout{s.dir}.labels_jsonl()));
  }
  // One pass writes camera by camera, each camera's frames in order: the shards' lines in that order.
  for (const json& camera : shards.front().manifest.at("cameras"))
    for (const auto& lines_of : by_camera)
      if (auto it = lines_of.find(camera.get<std::string>()); it != lines_of.end()) lines += it->second;
  for (const ShardRun& s : shards) MoveFrameFiles(s.dir, output.dir());
  WriteTextAtomically(LabelRunLayout{output.dir()}.labels_jsonl(), lines);
  RunProvenance run = shards.front().provenance;
  run.shard = nullptr;
  run.options["frame_begin"] = 0;
  run.options["frame_end"] = -1;
  WriteRunJson(output.dir(), run);
  WriteTextAtomically(LabelRunLayout{output.dir()}.manifest_json(), MergedManifest(shards, out).dump(2) + "\n");
  output.Publish();
  RemoveShards(shards);
}

void MergeValidationShards(const std::vector<fs::path>& shard_dirs, const fs::path& out) {
  std::vector<ShardRun> shards;
  for (const fs::path& dir : shard_dirs) shards.push_back(ReadShard(dir, ValidationRunLayout{dir}.summary_json()));
  CheckTiling(shards);
  PartialOutput output(out, "validation.json", "validation");
  int64_t total = 0;
  std::vector<std::map<std::string, std::vector<RecordCheck>>> by_camera;
  std::vector<std::map<std::string, std::vector<std::string>>> lines_by_camera;
  for (const ShardRun& s : shards) {
    ValidationRun run = ValidationRun::Read(s.dir);
    total += run.summary.at("records").get<int64_t>();
    auto& cameras = by_camera.emplace_back();
    for (RecordCheck& r : run.records) cameras[r.camera].push_back(std::move(r));
    lines_by_camera.push_back(LineListsByCamera(run.layout.records_jsonl()));
  }
  // One pass checks labels.jsonl's records in order: camera by camera, each camera's frames in order.
  const fs::path labels = shards.front().manifest.at("labels").get<std::string>();
  const json label_manifest = ReadJsonFile(LabelRunLayout{labels}.manifest_json());
  SessionValidation merged;
  std::vector<std::string> lines;  // lines[i] is merged.records[i]'s
  for (const json& camera : label_manifest.at("cameras")) {
    const std::string name = camera.get<std::string>();
    for (size_t k = 0; k < shards.size(); ++k) {
      for (RecordCheck& r : by_camera[k][name]) merged.records.push_back(std::move(r));
      for (std::string& line : lines_by_camera[k][name]) lines.push_back(std::move(line));
    }
  }
  MOCAP_CHECK(lines.size() == merged.records.size(), "validation shards: ", lines.size(), " lines for ", merged.records.size(), " records");
  merged.summary = Summarise(merged.records, total);
  ApplySessionWideStep(shards.front().provenance, merged, lines);
  std::string jsonl;
  for (const std::string& line : lines) jsonl += line;
  WriteMergedValidation(merged, jsonl, shards.front().manifest, output.dir(), out);
  RunProvenance run = shards.front().provenance;
  run.shard = nullptr;
  run.options["frame_begin"] = 0;
  run.options["frame_end"] = -1;
  WriteRunJson(output.dir(), run);
  output.Publish();
  RemoveShards(shards);
}

}  // namespace mocap::pipeline
