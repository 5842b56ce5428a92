// The plan as JSON: what `relabel --dry-run --json` prints and the plan file (WORK/plan.json) every task
// of an executor reads, so that a cluster job runs exactly what was planned.
#include "core/check.h"
#include "pipeline/json_read.h"
#include "pipeline/relabel_plan.h"

namespace mocap::pipeline {
namespace {

using nlohmann::json;

json StageJson(const StagePlan& stage) {
  json shards = json::array();
  for (const Shard& s : stage.shards) shards.push_back({{"index", s.index}, {"count", s.count}, {"begin", s.begin}, {"end", s.end}});
  return {{"run", stage.run}, {"why", stage.why}, {"options", stage.options}, {"shards", shards}, {"todo", stage.todo}};
}

StagePlan StageFromJson(const json& j, const std::string& where) {
  const JsonFields f(j, where);
  StagePlan stage;
  stage.run = f.Bool("run");
  stage.why = f.Strings("why");
  stage.options = f["options"];
  if (!f["shards"].is_array() || !f["todo"].is_array()) throw InputError(where, "shards and todo must be arrays");
  for (const json& s : f["shards"]) {
    const JsonFields sf(s, where + " shard");
    stage.shards.push_back({static_cast<int>(sf.Integer("index")), static_cast<int>(sf.Integer("count")),
                            sf.Integer("begin"), sf.Integer("end")});
  }
  for (const json& k : f["todo"]) {
    if (!k.is_number_integer() || k.get<int64_t>() < 0 || k.get<size_t>() >= stage.shards.size())
      throw InputError(where, "todo: a shard index out of range");
    stage.todo.push_back(k.get<int>());
  }
  return stage;
}

}  // namespace

json ToJson(const SessionPlan& s) {
  return {{"session", s.session_dir.string()}, {"rig", s.rig_file.string()},
          {"objects", s.objects_file.string()}, {"labels", s.labels_dir.string()},
          {"validation", s.validation_dir.string()}, {"frames", s.frames},
          {"label", StageJson(s.label)}, {"validate", StageJson(s.validate)}};
}

json ToJson(const RelabelPlan& plan) {
  json sessions = json::array();
  for (const SessionPlan& s : plan.sessions) sessions.push_back(ToJson(s));
  return {{"sessions", sessions}, {"seconds", plan.seconds}, {"files_checked", plan.files_checked},
          {"files_hashed", plan.files_hashed}};
}

RelabelPlan RelabelPlanFromJson(const json& json_plan, const std::string& where) {
  const JsonFields f(json_plan, where);
  RelabelPlan plan;
  plan.seconds = f.Number("seconds");
  plan.files_checked = f.Integer("files_checked"), plan.files_hashed = f.Integer("files_hashed");
  if (!f["sessions"].is_array()) throw InputError(where, "sessions must be an array");
  int i = 0;
  for (const json& j : f["sessions"]) {
    const std::string at = where + " sessions[" + std::to_string(i++) + "]";
    const JsonFields sf(j, at);
    SessionPlan s;
    s.session_dir = sf.String("session"), s.rig_file = sf.String("rig"), s.objects_file = sf.String("objects");
    s.labels_dir = sf.String("labels"), s.validation_dir = sf.String("validation");
    s.frames = sf.Integer("frames");
    s.label = StageFromJson(sf["label"], at + ".label");
    s.validate = StageFromJson(sf["validate"], at + ".validate");
    plan.sessions.push_back(std::move(s));
  }
  return plan;
}

}  // namespace mocap::pipeline
