#pragma once
// A validation run (docs/validation.md "Outputs"): the folder `mocaplabel validate` writes. Its layout,
// its validation.jsonl record and its one writer and one reader are here.
//
//   V/run.json          provenance (provenance.h)
//   V/validation.json   the summary; its presence marks a finished run
//   V/validation.jsonl  one record per checked label (a RecordCheck)
//   V/report.html       static report (validate/report_html.h)
#include <filesystem>
#include <nlohmann/json.hpp>

#include "pipeline/label_run.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

struct ValidationRunLayout {
  std::filesystem::path dir;
  std::filesystem::path records_jsonl() const { return dir / "validation.jsonl"; }
  std::filesystem::path summary_json() const { return dir / "validation.json"; }
  std::filesystem::path report_html() const { return dir / "report.html"; }
};

/// The validation.jsonl record of one check, and back (strict; errors name file:line and the field).
nlohmann::json ToJson(const RecordCheck& record);
RecordCheck RecordCheckFromJson(const nlohmann::json& json, const std::string& where);
/// validation.json: the summary, with `complete` and the inputs named.
nlohmann::json ValidationSummaryJson(const ValidationSummary& summary, const SessionCheckOptions& options,
                                     const std::filesystem::path& session_dir);

/// The checker's view of a label run: its records with a pose, those in [begin, end) counted.
LabelRunView LabelRunViewOf(const LabelRun& run, int64_t frame_begin = 0, int64_t frame_end = -1);

/// Writes the three files into `dir` (the summary last: its presence marks a finished run). `report_dir`
/// is where the report will finally live (its overlay links are relative to it).
void WriteValidationRun(const SessionValidation& validation, const SessionCheckOptions& options,
                        const std::filesystem::path& session_dir, const std::filesystem::path& dir,
                        const std::filesystem::path& report_dir);

/// A finished validation run read back. Throws InputError naming the file for a folder that is not one.
struct ValidationRun {
  ValidationRunLayout layout;
  nlohmann::json summary;
  std::vector<RecordCheck> records;
  static ValidationRun Read(const std::filesystem::path& dir);
};

}  // namespace mocap::pipeline
