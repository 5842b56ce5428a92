#pragma once
// `mocaplabel export` as a library call (docs/export.md): sessions with their label (and validation)
// runs into one dataset folder, published whole (pipeline/publish.h) with a run.json naming every input
// run; an export whose inputs and options are unchanged writes nothing.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "exporters/bop/bop_writer.h"
#include "exporters/coco/coco_writer.h"
#include "exporters/segpairs/segpairs_writer.h"
#include "exporters/tum/tum_writer.h"
#include "exporters/dataset/selection.h"
#include "pipeline/stage.h"

namespace mocap {
class ProgressSink;
}

namespace mocap::exporters {

enum class ExportFormat { kBop, kCoco, kSegpairs, kTum };
std::string_view ToString(ExportFormat format);
/// "bop", "coco", "segpairs", "tum"; InputError otherwise.
ExportFormat ExportFormatFromName(const std::string& name);

struct ExportOptions {
  ExportFormat format = ExportFormat::kBop;
  ExportFilterOptions filters;
  ExportSplitOptions splits;
  BopOptions bop;
  CocoOptions coco;
  SegPairsOptions segpairs;
  TumExportOptions tum;
  int threads = 0;  ///< 0: one per core
  void check() const;
};
/// What changes the output (run.json `options`; not threads).
nlohmann::json ToJson(const ExportOptions& options);

struct ExportResult {
  std::filesystem::path out_dir;
  /// The dataset at out_dir was made from the same inputs (unchanged) with the same options: nothing
  /// was written.
  bool up_to_date = false;
  SelectionSummary selection;
  WriteSummary written;
  double seconds = 0;
  nlohmann::json ToJson() const;  ///< the summary `export.json` holds and `--json` prints
};

/// An export.json read back (the summary of an earlier export).
ExportResult ExportResultFromJson(const nlohmann::json& json, const std::filesystem::path& out_dir);

/// Exports `inputs` as `options.format` into `out` (published whole: written into <out>.partial; `out`
/// must be absent, empty, or an earlier export, which is replaced). Throws InputError for bad inputs
/// (LoadDataset) or a failed write; nothing half-written is left at `out` then.
ExportResult RunExport(const std::vector<ExportInput>& inputs, const ExportOptions& options,
                       const std::filesystem::path& out, const std::vector<std::string>& command,
                       ProgressSink* progress = nullptr);

/// The export as a pipeline stage (the demo's last): the context's session, label run and validation run
/// into out_dir/dataset as `options.format`; its summary goes into the context's results.
pipeline::Stage MakeExportStage(const ExportOptions& options);

}  // namespace mocap::exporters
