#pragma once
// The files of `mocaplabel validate` (docs/validation.md "Outputs"): validation.jsonl (one record per
// frame and labelled object), validation.json (the summary) and report.html (static, inline SVG plots,
// readable offline). Written into <out>.partial and renamed to <out> only when complete.
#include <filesystem>
#include <nlohmann/json.hpp>

#include "validate/session_check.h"

namespace mocap {

/// The validation.jsonl record of one check.
nlohmann::json ValidationRecordJson(const RecordCheck& record);
/// validation.json: the summary, with `complete` and the inputs named.
nlohmann::json ValidationSummaryJson(const ValidationSummary& summary, const SessionCheckOptions& options,
                                     const std::filesystem::path& session_dir);
/// The HTML report (plots mark the accept thresholds of `verdict`). `out_dir` is where it will live (overlay links are made relative to it).
std::string ValidationReportHtml(const SessionValidation& validation, const VerdictOptions& verdict,
                                 const std::filesystem::path& out_dir);

/// Writes the three files under out_dir (via out_dir.partial). Throws InputError when out_dir exists
/// and is not an earlier validation output, or a write fails (the partial output stays at .partial).
void WriteValidation(const SessionValidation& validation, const SessionCheckOptions& options,
                     const std::filesystem::path& session_dir, const std::filesystem::path& out_dir);

/// The validator in one call, for the CLI and the demo: CheckSession, then WriteValidation when
/// `out_dir` is not empty. Returns the checks (summary.segicp_success_rate and summary.verdicts are what
/// the demo prints).
SessionValidation ValidateSession(const SessionReader& session, const std::vector<ValidationObject>& objects,
                                  const SessionCheckOptions& options, const std::filesystem::path& out_dir);

}  // namespace mocap
