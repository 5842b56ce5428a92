#include "pipeline/publish.h"

#include <exception>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/check.h"
#include "pipeline/yaml_write.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

void Relocate(nlohmann::json& j, const std::string& from, const std::string& to) {
  if (j.is_string()) {
    const std::string& s = j.get_ref<const std::string&>();
    if (s.compare(0, from.size(), from) == 0 && (s.size() == from.size() || s[from.size()] == '/'))
      j = to + s.substr(from.size());
  } else if (j.is_structured()) {
    for (auto& item : j) Relocate(item, from, to);
  }
}

bool IsRunFile(const fs::path& file) {
  const std::string name = file.filename().string();
  return name == "run.json" || name == "label_manifest.json" || name == "validation.json" || name == "demo.json";
}

}  // namespace

fs::path PartialPath(const fs::path& out) {
  fs::path partial = out;
  partial += ".partial";
  return partial;
}

PartialOutput::PartialOutput(fs::path out, std::string marker, std::string kind)
    : out_(std::move(out)), partial_(PartialPath(out_)), marker_(std::move(marker)), kind_(std::move(kind)) {
  if (out_.empty()) throw InputError(kind_, "no output folder given (--out)");
  if (fs::exists(out_) && (!fs::is_directory(out_) || (!fs::is_empty(out_) && !fs::exists(out_ / marker_))))
    throw InputError(out_.string(), Str("exists and is not an earlier ", kind_, " output (no ", marker_, "); choose another --out"));
  std::error_code error;
  fs::remove_all(partial_, error);
  fs::create_directories(partial_, error);
  if (error) throw InputError(partial_.string(), Str("cannot be created: ", error.message()));
  exceptions_at_start_ = std::uncaught_exceptions();
}

PartialOutput::~PartialOutput() {
  if (published_ || std::uncaught_exceptions() <= exceptions_at_start_) return;
  std::error_code ignored;
  fs::remove_all(partial_, ignored);
}

void PartialOutput::Publish() {
  MOCAP_CHECK(fs::exists(partial_ / marker_), kind_, " output published without its ", marker_);
  const std::string from = fs::absolute(partial_).lexically_normal().string();
  const std::string to = fs::absolute(out_).lexically_normal().string();
  // Run files sit at the top or one folder down (the demo's labels/, validation/): the walk stops
  // there rather than visiting every frame file of a long run.
  for (auto it = fs::recursive_directory_iterator(partial_); it != fs::recursive_directory_iterator(); ++it) {
    if (it.depth() >= 1) it.disable_recursion_pending();
    if (it->is_regular_file() && IsRunFile(it->path())) RelocateJsonPaths(it->path(), from, to);
  }
  std::error_code error;
  fs::remove_all(out_, error);
  fs::rename(partial_, out_, error);
  if (error) throw InputError(out_.string(), Str("could not be put in place: ", error.message(), " (the output is in ", partial_.string(), ")"));
  published_ = true;
}

void RelocateJsonPaths(const fs::path& file, const std::string& from, const std::string& to) {
  std::ifstream in(file);
  nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return;  // not ours to fix
  const std::string before = j.dump();
  Relocate(j, from, to);
  if (j.dump() != before) WriteTextAtomically(file, j.dump(2) + "\n");
}

}  // namespace mocap::pipeline
