#include "pipeline/relabel_plan.h"

#include <chrono>
#include <fstream>
#include <map>
#include <optional>

#include "core/check.h"
#include "pipeline/build_info.h"
#include "pipeline/json_read.h"
#include "pipeline/label_stage.h"
#include "pipeline/object_library.h"
#include "pipeline/provenance.h"
#include "pipeline/run_provenance.h"
#include "pipeline/shards.h"
#include "session/manifest.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path Normal(const fs::path& p) { return fs::absolute(p).lexically_normal(); }

/// "1.2.10" > "1.2.9": numeric fields compared in order.
bool NewerVersion(const std::string& a, const std::string& b) {
  auto fields = [](const std::string& v) {
    std::vector<long> out;
    size_t i = 0;
    while (i < v.size()) {
      size_t end = v.find('.', i);
      if (end == std::string::npos) end = v.size();
      try { out.push_back(std::stol(v.substr(i, end - i))); } catch (...) { out.push_back(0); }
      i = end + 1;
    }
    return out;
  };
  return fields(a) > fields(b);
}

/// Per planning call: object libraries and their per-session digests, read once per file.
struct Libraries {
  std::map<fs::path, ObjectLibrary> by_file;
  const ObjectLibrary& Get(const fs::path& file) {
    auto it = by_file.find(file);
    if (it == by_file.end()) it = by_file.emplace(file, ReadObjectLibrary(file)).first;
    return it->second;
  }
};

struct Recorded {
  RunProvenance run;
  fs::path Input(const std::string& role) const {
    for (const InputRecord& in : run.inputs)
      if (in.role == role) return in.path;
    return {};
  }
};

/// run.json of an existing finished run, checked for what relabel cannot redo.
Recorded ReadFinishedRun(const fs::path& dir, const std::string& kind) {
  if (!fs::exists(dir / "run.json"))
    throw InputError((dir / "run.json").string(),
                     "missing: the run has no provenance (made by an older mocaplabel, or copied without it), so "
                     "relabel cannot tell what it read; move the run away to make it again");
  Recorded r{ReadRunJson(dir)};
  const std::string where = (dir / "run.json").string();
  if (r.run.kind != kind) throw InputError(where, "a " + r.run.kind + " run, not a " + kind + " run");
  if (!r.run.shard.is_null()) throw InputError(where, "the run of one shard, not a whole run: merge or remove it");
  const std::string& ours = CurrentBuildInfo().version;
  if (NewerVersion(r.run.tool_version, ours))
    throw InputError(where, "made by mocaplabel " + r.run.tool_version + ", newer than this one (" + ours +
                                "); relabel with that version or newer");
  return r;
}

/// Judges the runs of one session against the inputs it would read now. The library's digests of the
/// session's objects are computed once per session, whatever the number of runs and shards judged.
class Judge {
 public:
  Judge(const ObjectLibrary& library, const SessionManifest& manifest, HashCache& cache, RelabelPlan& plan)
      : library_(library), objects_now_(ObjectsInSession(library, manifest)), cache_(cache), plan_(plan) {}

  /// The changes that matter to a run: CheckStale, with the objects file and meshes judged by the entries
  /// of the objects in the session when the run recorded them.
  std::vector<std::string> Changes(const Recorded& rec, std::map<std::string, fs::path> overrides) const {
    std::vector<std::string> why;
    const bool per_object = rec.run.options.contains("objects_in_session");
    for (const LibraryObject& o : library_.objects)
      if (objects_now_.contains(o.name) && !rec.Input("mesh:" + o.name).empty()) overrides["mesh:" + o.name] = o.mesh_path;
    const StaleReport report = CheckStale(rec.run, overrides, cache_);
    plan_.files_checked += report.files_checked, plan_.files_hashed += report.files_hashed;
    for (const InputChange& c : report.changes) {
      if (per_object && c.role == "objects") continue;  // judged per object below
      if (per_object && c.role.rfind("mesh:", 0) == 0 && !objects_now_.contains(c.role.substr(5))) continue;
      why.push_back(c.role + " " + c.path + ": " + c.what);
    }
    if (!per_object) return why;
    const json& recorded = rec.run.options["objects_in_session"];
    for (const auto& [name, digest] : objects_now_.items()) {
      if (!recorded.contains(name)) why.push_back("object " + name + ": new in the session's library entries");
      else if (recorded[name] != digest) why.push_back("object " + name + ": its objects.yaml entry changed");
    }
    for (const auto& [name, digest] : recorded.items())
      if (!objects_now_.contains(name)) why.push_back("object " + name + ": no longer in the library");
    return why;
  }

  /// A shard's run is finished and reads what the whole run would read.
  bool ShardDone(const fs::path& dir, const std::string& marker, const std::string& kind,
                 const std::map<std::string, fs::path>& overrides) const {
    if (!fs::exists(dir / marker) || !fs::exists(dir / "run.json")) return false;
    try {
      const Recorded rec{ReadRunJson(dir)};
      return rec.run.kind == kind && Changes(rec, overrides).empty();
    } catch (const InputError&) {
      return false;  // an unreadable shard is redone
    }
  }

 private:
  const ObjectLibrary& library_;
  const json objects_now_;
  HashCache& cache_;
  RelabelPlan& plan_;
};

void SplitStage(StagePlan& stage, int64_t frames, int64_t shard_frames) {
  const int count = shard_frames > 0 ? static_cast<int>(std::max<int64_t>(1, (frames + shard_frames - 1) / shard_frames)) : 1;
  stage.shards = count == 1 ? std::vector<Shard>{Shard{}} : SplitShards(frames, count);
}

class Planner {
 public:
  Planner(const RelabelPlanOptions& options, HashCache& cache, RelabelPlan& plan)
      : options_(options), cache_(cache), plan_(plan) {}

  SessionPlan Plan(const fs::path& session_arg) {
    SessionPlan s;
    s.session_dir = Normal(session_arg);
    if (!fs::exists(s.session_dir / "manifest.json"))
      throw InputError(session_arg.string(), fs::exists(s.session_dir) ? "not a session: no manifest.json"
                                                                       : "no such session (moved or removed?)");
    const SessionManifest manifest = LoadManifest(s.session_dir);
    s.labels_dir = s.session_dir / "labels", s.validation_dir = s.session_dir / "validation";
    s.frames = SessionFrames(s.session_dir, manifest);
    const std::optional<Recorded> label_run = ReadLabelRun(s);  // settles the rig and library files
    const Judge judge(libraries_.Get(s.objects_file), manifest, cache_, plan_);
    PlanLabel(s, label_run, judge);
    if (options_.validate) PlanValidate(s, judge);
    return s;
  }

 private:
  void CheckNotMoved(const Recorded& rec, const SessionPlan& s, StagePlan& stage, const fs::path& dir) {
    const fs::path recorded = rec.Input("session");
    if (recorded.empty() || Normal(recorded) == s.session_dir) return;
    if (!options_.relabel_moved)
      throw InputError((dir / "run.json").string(),
                       "made from the session at " + recorded.string() + ", not " + s.session_dir.string() +
                           ": the session was moved or copied; pass --relabel-moved to relabel it where it is");
    stage.why.push_back("the session moved from " + recorded.string());
  }

  /// The inputs given on the command line that replace recorded ones: a validation run reads the rig
  /// through its label run, and its label run is the session's.
  std::map<std::string, fs::path> Overrides(const SessionPlan& s, const std::string& kind) const {
    std::map<std::string, fs::path> o;
    if (!options_.rig_file.empty() && kind == "label") o["rig"] = s.rig_file;
    if (!options_.objects_file.empty()) o["objects"] = s.objects_file;
    if (kind == "validation") o["labels"] = s.labels_dir;
    return o;
  }

  /// The finished label run, if any; sets the session's rig and library files (given, else recorded).
  std::optional<Recorded> ReadLabelRun(SessionPlan& s) {
    s.rig_file = options_.rig_file.empty() ? fs::path() : Normal(options_.rig_file);
    s.objects_file = Normal(FindObjectsFile(s.session_dir, options_.objects_file));
    if (!fs::exists(s.labels_dir / "label_manifest.json")) return std::nullopt;
    Recorded rec = ReadFinishedRun(s.labels_dir, "label");
    if (options_.rig_file.empty() && !rec.Input("rig").empty()) s.rig_file = rec.Input("rig");
    if (options_.objects_file.empty() && !rec.Input("objects").empty()) s.objects_file = rec.Input("objects");
    return rec;
  }

  void PlanLabel(SessionPlan& s, const std::optional<Recorded>& rec, const Judge& judge) {
    StagePlan& stage = s.label;
    if (!rec) {
      stage.why.push_back(fs::exists(s.labels_dir) ? "the label run is unfinished" : "no label run yet");
      stage.options = ToJson(options_.label_options);
    } else {
      CheckNotMoved(*rec, s, stage, s.labels_dir);
      stage.options = rec->run.options;
      stage.options.erase("objects_in_session");
      if (stage.why.empty()) stage.why = judge.Changes(*rec, Overrides(s, "label"));
    }
    stage.run = options_.label && !stage.why.empty();
    if (!options_.label && !stage.why.empty()) stage.why.insert(stage.why.begin(), "stale, but not asked for:");
    if (stage.run) Shards(s, stage, s.labels_dir, "label_manifest.json", "label", judge);
  }

  void PlanValidate(SessionPlan& s, const Judge& judge) {
    StagePlan& stage = s.validate;
    const bool exists = fs::exists(s.validation_dir / "validation.json");
    if (!exists) {
      stage.why.push_back(fs::exists(s.validation_dir) ? "the validation run is unfinished" : "no validation run yet");
      stage.options = ToJson(options_.check_options);
    } else {
      const Recorded rec = ReadFinishedRun(s.validation_dir, "validation");
      CheckNotMoved(rec, s, stage, s.validation_dir);
      stage.options = rec.run.options;
      stage.options.erase("objects_in_session");
      if (s.label.run) stage.why.push_back("its label run is redone");
      if (stage.why.empty()) stage.why = judge.Changes(rec, Overrides(s, "validation"));
    }
    stage.run = !stage.why.empty();
    if (!stage.run) return;
    if (!s.label.run && !fs::exists(s.labels_dir / "label_manifest.json"))
      throw InputError(s.labels_dir.string(), "no finished label run to validate; relabel with the label stage");
    Shards(s, stage, s.validation_dir, "validation.json", "validation", judge);
  }

  void Shards(const SessionPlan& s, StagePlan& stage, const fs::path& out, const std::string& marker,
              const std::string& kind, const Judge& judge) {
    SplitStage(stage, s.frames, options_.shard_frames);
    const std::map<std::string, fs::path> overrides = Overrides(s, kind);
    const bool inputs_settled = kind == "label" || !s.label.run;  // validation shards wait for the labels
    for (size_t k = 0; k < stage.shards.size(); ++k) {
      const bool done = stage.shards.size() > 1 && inputs_settled &&
                        judge.ShardDone(ShardDir(out, stage.shards[k]), marker, kind, overrides);
      if (!done) stage.todo.push_back(static_cast<int>(k));
    }
  }

  const RelabelPlanOptions& options_;
  HashCache& cache_;
  RelabelPlan& plan_;
  Libraries libraries_;
};

}  // namespace

void RelabelPlanOptions::check() const {
  if (shard_frames < 0) throw InputError("relabel", "--shard-frames must be >= 0");
  if (!label && !validate) throw InputError("relabel", "no stage to run: --stages needs label or validate");
  label_options.check();
  // check_options are checked per session, once its label run is known (SessionCheckOptions::check)
}

int64_t SessionFrames(const fs::path& session_dir) { return SessionFrames(session_dir, LoadManifest(session_dir)); }

int64_t SessionFrames(const fs::path& session_dir, const SessionManifest& manifest) {
  int64_t longest = 0;
  for (const CameraStreamInfo& camera : manifest.cameras) {
    std::ifstream in(session_dir / "cameras" / camera.name / "frames.jsonl", std::ios::binary);
    int64_t lines = 0;
    for (std::string line; std::getline(in, line);) lines += line.empty() ? 0 : 1;
    longest = std::max(longest, lines);
  }
  return longest;
}

int64_t RelabelPlan::FramesToRun(bool validate) const {
  int64_t frames = 0;
  for (const SessionPlan& s : sessions) {
    const StagePlan& stage = validate ? s.validate : s.label;
    if (!stage.run) continue;
    for (int k : stage.todo) frames += s.ShardFrames(stage.shards[static_cast<size_t>(k)]);
  }
  return frames;
}

RelabelPlan PlanRelabel(const std::vector<fs::path>& sessions, const RelabelPlanOptions& options, HashCache& cache) {
  options.check();
  const auto start = std::chrono::steady_clock::now();
  RelabelPlan plan;
  Planner planner(options, cache, plan);
  for (const fs::path& session : sessions) plan.sessions.push_back(planner.Plan(session));
  for (size_t i = 0; i < plan.sessions.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (plan.sessions[i].session_dir == plan.sessions[j].session_dir)
        throw InputError(sessions[i].string(), "the session is given twice");
  plan.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return plan;
}

}  // namespace mocap::pipeline
