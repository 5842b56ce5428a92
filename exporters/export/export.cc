#include "exporters/export/export.h"

#include <chrono>

#include "core/check.h"
#include "core/progress.h"
#include "pipeline/json_read.h"
#include "pipeline/provenance.h"
#include "pipeline/publish.h"
#include "pipeline/run_provenance.h"
#include "session/durable_file.h"

namespace mocap::exporters {
namespace fs = std::filesystem;
namespace {

constexpr const char* kMarker = "export.json";

/// run.json's inputs: each session, label run and validation run (their defining files), each object
/// library and every mesh exported.
std::vector<pipeline::InputSpec> InputSpecs(const Dataset& dataset) {
  std::vector<pipeline::InputSpec> specs;
  std::map<std::string, int> count;
  for (const auto& [role, path] : dataset.inputs) {
    const std::string numbered = Str(role, ":", ++count[role]);
    if (role == "session") specs.push_back(pipeline::SessionInput(path)), specs.back().role = numbered;
    else if (role == "labels") specs.push_back({numbered, path, true, {"labels.jsonl", "label_manifest.json", "run.json"}});
    else if (role == "validation") specs.push_back({numbered, path, true, {"validation.jsonl", "validation.json"}});
    else specs.push_back({numbered, path, false, {}});
  }
  for (const pipeline::LibraryObject& object : dataset.objects.objects)
    specs.push_back({"mesh:" + object.name, object.mesh_path, false, {}});
  return specs;
}

/// Whether `out` holds an export of exactly these inputs (unchanged since) and options.
bool UpToDate(const fs::path& out, const std::vector<pipeline::InputSpec>& specs, const nlohmann::json& options) {
  if (!fs::exists(out / kMarker) || !fs::exists(out / "run.json")) return false;
  const pipeline::RunProvenance run = pipeline::ReadRunJson(out);
  if (run.kind != "export" || run.options != options || run.inputs.size() != specs.size()) return false;
  for (size_t i = 0; i < specs.size(); ++i)
    if (run.inputs[i].role != specs[i].role || fs::path(run.inputs[i].path) != fs::absolute(specs[i].path).lexically_normal())
      return false;
  pipeline::HashCache cache;
  return !pipeline::CheckStale(run, {}, cache).stale;
}

WriteSummary WriteFormat(const Dataset& dataset, const fs::path& dir, const ExportOptions& options) {
  switch (options.format) {
    case ExportFormat::kBop: {
      BopOptions bop = options.bop;
      bop.threads = options.threads;
      return WriteBop(dataset, dir, bop);
    }
    case ExportFormat::kCoco: {
      CocoOptions coco = options.coco;
      coco.threads = options.threads;
      return WriteCoco(dataset, dir, coco);
    }
    case ExportFormat::kSegpairs: {
      SegPairsOptions segpairs = options.segpairs;
      segpairs.threads = options.threads;
      return WriteSegPairs(dataset, dir, segpairs);
    }
    case ExportFormat::kTum: {
      TumExportOptions tum = options.tum;
      tum.threads = options.threads;
      return WriteTum(dataset, dir, tum);
    }
  }
  throw InputError("export", Str("unknown format '", ToString(options.format), "'"));
}

}  // namespace

void ExportOptions::check() const {
  filters.check();
  splits.check();
  bop.check();
  coco.check();
  segpairs.check();
  tum.check();
  if (threads < 0) throw InputError("ExportOptions", "threads must be >= 0");
}

ExportResult RunExport(const std::vector<ExportInput>& inputs, const ExportOptions& options, const fs::path& out,
                       const std::vector<std::string>& command, ProgressSink* sink) {
  const auto start = std::chrono::steady_clock::now();
  options.check();
  Progress progress(sink, "export", 3, "steps");
  ExportResult result;
  result.out_dir = fs::absolute(out).lexically_normal();
  Dataset dataset = LoadDataset(inputs);
  const std::vector<pipeline::InputSpec> specs = InputSpecs(dataset);
  const nlohmann::json options_json = ToJson(options);
  progress.Advance();
  if (UpToDate(result.out_dir, specs, options_json)) {
    result = ExportResultFromJson(pipeline::ReadJsonFile(result.out_dir / kMarker), result.out_dir);
    result.up_to_date = true;
    progress.Finish();
    return result;
  }
  pipeline::PartialOutput partial(result.out_dir, kMarker, "export");
  result.selection = SelectFrames(dataset, options.filters, options.splits);
  progress.Advance();
  result.written = WriteFormat(dataset, partial.dir(), options);
  pipeline::WriteProvenance(partial.dir(), "export", command, options_json, specs);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WriteFileAtomically(partial.dir() / kMarker, result.ToJson().dump(2) + "\n");
  partial.Publish();
  progress.Finish();
  return result;
}

pipeline::Stage MakeExportStage(const ExportOptions& options) {
  pipeline::Stage stage;
  stage.name = "export";
  stage.inputs = [](const pipeline::PipelineContext& c) { return std::vector<fs::path>{c.session_dir, c.labels_dir}; };
  stage.outputs = [](const pipeline::PipelineContext& c) { return std::vector<fs::path>{c.out_dir / "dataset"}; };
  stage.run = [options](pipeline::PipelineContext& c, const pipeline::Shard&) {
    ExportOptions o = options;
    o.threads = c.threads;
    const ExportInput input{c.session_dir, c.labels_dir, c.validation_dir, c.validation_dir.empty()};
    const ExportResult result = RunExport({input}, o, c.out_dir / "dataset", c.command, c.progress);
    c.results["export"] = result.ToJson();
    c.outputs["dataset"] = result.out_dir.string();
  };
  return stage;
}

}  // namespace mocap::exporters
