#include "pipeline/relabel_tasks.h"

#include <set>

#include "core/check.h"
#include "pipeline/label_stage.h"
#include "pipeline/run_provenance.h"
#include "pipeline/shards.h"
#include "pipeline/validate_stage.h"
#include "pipeline/validation_run.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const StagePlan& Of(const SessionPlan& s, RelabelStage stage) { return stage == RelabelStage::kLabel ? s.label : s.validate; }
const fs::path& OutOf(const SessionPlan& s, RelabelStage stage) {
  return stage == RelabelStage::kLabel ? s.labels_dir : s.validation_dir;
}

/// Where a task writes: the run itself for a whole-session shard, else the shard's folder.
fs::path TaskOut(const SessionPlan& s, RelabelStage stage, const Shard& shard) {
  return shard.whole() ? OutOf(s, stage) : ShardDir(OutOf(s, stage), shard);
}

}  // namespace

std::string_view ToString(RelabelStage stage) { return stage == RelabelStage::kLabel ? "label" : "validate"; }

std::vector<RelabelTask> StageTasks(const RelabelPlan& plan, RelabelStage stage) {
  std::vector<RelabelTask> tasks;
  for (size_t i = 0; i < plan.sessions.size(); ++i) {
    const SessionPlan& s = plan.sessions[i];
    const StagePlan& sp = Of(s, stage);
    if (!sp.run) continue;
    for (int k : sp.todo) tasks.push_back({static_cast<int>(i), k, s.ShardFrames(sp.shards[static_cast<size_t>(k)])});
  }
  return tasks;
}

bool StageNeedsMerge(const RelabelPlan& plan, RelabelStage stage) {
  for (const SessionPlan& s : plan.sessions)
    if (Of(s, stage).run && s.merged(Of(s, stage))) return true;
  return false;
}

void RunRelabelTask(const RelabelPlan& plan, RelabelStage stage, const RelabelTask& task, int threads,
                    const std::vector<std::string>& command) {
  MOCAP_CHECK(task.session >= 0 && static_cast<size_t>(task.session) < plan.sessions.size(), "task of session ", task.session);
  const SessionPlan& s = plan.sessions[static_cast<size_t>(task.session)];
  const StagePlan& sp = Of(s, stage);
  MOCAP_CHECK(task.shard >= 0 && static_cast<size_t>(task.shard) < sp.shards.size(), "task of shard ", task.shard);
  const Shard& shard = sp.shards[static_cast<size_t>(task.shard)];
  const std::string where = s.session_dir.string() + " (relabel plan)";
  if (stage == RelabelStage::kLabel) {
    LabelRunRequest request;
    request.session_dir = s.session_dir, request.rig_file = s.rig_file, request.objects_file = s.objects_file;
    request.out_dir = TaskOut(s, stage, shard);
    request.label = LabelOptionsFromJson(sp.options, where);
    request.label.threads = threads;
    request.shard = shard;
    request.command = command;
    RunLabel(request);
  } else {
    ValidateRunRequest request;
    request.session_dir = s.session_dir, request.labels_dir = s.labels_dir, request.objects_file = s.objects_file;
    request.out_dir = TaskOut(s, stage, shard);
    request.check = SessionCheckOptionsFromJson(sp.options, where);
    request.check.threads = threads;
    request.shard = shard;
    request.command = command;
    RunValidate(request);
  }
}

void MergeRelabelStage(const RelabelPlan& plan, RelabelStage stage) {
  for (const SessionPlan& s : plan.sessions) {
    const StagePlan& sp = Of(s, stage);
    if (!sp.run || !s.merged(sp)) continue;
    std::vector<fs::path> dirs;
    for (const Shard& shard : sp.shards) dirs.push_back(ShardDir(OutOf(s, stage), shard));
    if (stage == RelabelStage::kLabel) MergeLabelShards(dirs, s.labels_dir);
    else MergeValidationShards(dirs, s.validation_dir);
  }
}

std::map<std::string, std::string> RunVerdicts(const fs::path& validation_dir) {
  std::map<std::string, std::string> verdicts;
  if (!fs::exists(ValidationRunLayout{validation_dir}.summary_json())) return verdicts;
  for (const RecordCheck& r : ValidationRun::Read(validation_dir).records)
    verdicts[r.camera + "/" + std::to_string(r.index) + "/" + r.name + "/" + std::to_string(r.instance)] =
        std::string(ToString(r.check.verdict));
  return verdicts;
}

json VerdictChanges(const std::map<std::string, std::string>& before, const std::map<std::string, std::string>& after) {
  std::set<std::string> keys;
  for (const auto& [k, v] : before) keys.insert(k);
  for (const auto& [k, v] : after) keys.insert(k);
  json out = {{"changed", 0}, {"unchanged", 0}, {"transitions", json::object()}, {"objects", json::object()}};
  for (const std::string& key : keys) {
    const auto b = before.find(key), a = after.find(key);
    const std::string from = b == before.end() ? "none" : b->second, to = a == after.end() ? "none" : a->second;
    if (from == to) {
      out["unchanged"] = out["unchanged"].get<int64_t>() + 1;
      continue;
    }
    const std::string transition = from + "->" + to;
    // key: camera/index/object/instance
    const size_t object_end = key.rfind('/'), object_begin = key.rfind('/', object_end - 1) + 1;
    const std::string object = key.substr(object_begin, object_end - object_begin);
    out["changed"] = out["changed"].get<int64_t>() + 1;
    out["transitions"][transition] = out["transitions"].value(transition, 0) + 1;
    json& per_object = out["objects"][object];
    if (per_object.is_null()) per_object = json::object();
    per_object[transition] = per_object.value(transition, 0) + 1;
  }
  return out;
}

}  // namespace mocap::pipeline
