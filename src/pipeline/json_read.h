#pragma once
// Strict reading of the JSON files the pipeline writes (labels.jsonl, validation.jsonl, run.json, the
// manifests): a missing or mistyped field is an InputError naming the file, the line and the field.
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mocap::pipeline {

/// Typed access to the fields of one JSON object.
class JsonFields {
 public:
  /// Throws when `json` is not an object.
  JsonFields(const nlohmann::json& json, std::string where);
  bool Has(const char* key) const { return json_.contains(key); }
  const nlohmann::json& operator[](const char* key) const;  ///< throws when missing
  std::string String(const char* key) const;
  int64_t Integer(const char* key) const;
  double Number(const char* key) const;  ///< finite
  bool Bool(const char* key) const;
  std::optional<double> OptionalNumber(const char* key) const;  ///< null or absent: nullopt
  std::vector<double> Numbers(const char* key, size_t count) const;
  Eigen::Vector3d Vector3(const char* key) const;
  std::array<int, 4> Box(const char* key) const;
  std::vector<std::string> Strings(const char* key) const;
  const std::string& where() const { return where_; }

 private:
  [[noreturn]] void Fail(const char* key, const std::string& expected) const;
  const nlohmann::json& json_;
  std::string where_;
};

/// A whole JSON file; InputError naming the file when missing or malformed.
nlohmann::json ReadJsonFile(const std::filesystem::path& file);
/// A JSON-lines file as ("file:line", object) pairs, empty lines skipped; a line that is not JSON, or a
/// last line without its newline (a torn write), is an InputError naming file:line.
std::vector<std::pair<std::string, nlohmann::json>> ReadJsonLines(const std::filesystem::path& file);

}  // namespace mocap::pipeline
