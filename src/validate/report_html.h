#pragma once
// The static HTML report of `mocaplabel validate` (docs/validation.md "Outputs"): summary tables and
// inline SVG plots, readable offline. The validation run that holds it is the pipeline's
// (pipeline/validation_run.h).
#include <filesystem>
#include <string>

#include "validate/session_check.h"

namespace mocap {

/// The report's HTML (plots mark the accept thresholds of `verdict`). `out_dir` is where it will live
/// (overlay links are made relative to it).
std::string ValidationReportHtml(const SessionValidation& validation, const VerdictOptions& verdict,
                                 const std::filesystem::path& out_dir);

}  // namespace mocap
