#include "pipeline/json_read.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/check.h"

namespace mocap::pipeline {

JsonFields::JsonFields(const nlohmann::json& json, std::string where) : json_(json), where_(std::move(where)) {
  if (!json.is_object()) throw InputError(where_, "expected a JSON object");
}

void JsonFields::Fail(const char* key, const std::string& expected) const {
  if (!json_.contains(key)) throw InputError(where_, Str("missing field \"", key, "\""));
  throw InputError(where_, Str("field \"", key, "\" must be ", expected, " (got ", json_[key].dump(), ")"));
}

const nlohmann::json& JsonFields::operator[](const char* key) const {
  if (!json_.contains(key)) Fail(key, "present");
  return json_[key];
}

std::string JsonFields::String(const char* key) const {
  if (!json_.contains(key) || !json_[key].is_string()) Fail(key, "a string");
  return json_[key].get<std::string>();
}

int64_t JsonFields::Integer(const char* key) const {
  if (!json_.contains(key) || !json_[key].is_number_integer()) Fail(key, "an integer");
  return json_[key].get<int64_t>();
}

double JsonFields::Number(const char* key) const {
  if (!json_.contains(key) || !json_[key].is_number() || !std::isfinite(json_[key].get<double>())) Fail(key, "a number");
  return json_[key].get<double>();
}

bool JsonFields::Bool(const char* key) const {
  if (!json_.contains(key) || !json_[key].is_boolean()) Fail(key, "true or false");
  return json_[key].get<bool>();
}

std::optional<double> JsonFields::OptionalNumber(const char* key) const {
  if (!json_.contains(key) || json_[key].is_null()) return std::nullopt;
  return Number(key);
}

std::vector<double> JsonFields::Numbers(const char* key, size_t count) const {
  const auto bad = [&] { Fail(key, Str("an array of ", count, " numbers")); };
  if (!json_.contains(key) || !json_[key].is_array() || json_[key].size() != count) bad();
  std::vector<double> out;
  for (const auto& v : json_[key]) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) bad();
    out.push_back(v.get<double>());
  }
  return out;
}

Eigen::Vector3d JsonFields::Vector3(const char* key) const {
  const std::vector<double> v = Numbers(key, 3);
  return {v[0], v[1], v[2]};
}

std::array<int, 4> JsonFields::Box(const char* key) const {
  const auto bad = [&] { Fail(key, "an array of 4 integers"); };
  if (!json_.contains(key) || !json_[key].is_array() || json_[key].size() != 4) bad();
  std::array<int, 4> out{};
  for (size_t i = 0; i < 4; ++i) {
    if (!json_[key][i].is_number_integer()) bad();
    out[i] = json_[key][i].get<int>();
  }
  return out;
}

std::vector<std::string> JsonFields::Strings(const char* key) const {
  if (!json_.contains(key) || !json_[key].is_array()) Fail(key, "an array of strings");
  std::vector<std::string> out;
  for (const auto& v : json_[key]) {
    if (!v.is_string()) Fail(key, "an array of strings");
    out.push_back(v.get<std::string>());
  }
  return out;
}

nlohmann::json ReadJsonFile(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "missing or unreadable");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file.string(), Str("not valid JSON (", e.what(), ")"));
  }
}

std::vector<std::pair<std::string, nlohmann::json>> ReadJsonLines(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "missing or unreadable");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::vector<std::pair<std::string, nlohmann::json>> out;
  size_t start = 0;
  for (int64_t number = 1; start < text.size(); ++number) {
    const size_t end = text.find('\n', start);
    const std::string where = Str(file.string(), ":", number);
    if (end == std::string::npos) throw InputError(where, "last line has no newline (a torn write?)");
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.empty()) continue;
    try {
      out.emplace_back(where, nlohmann::json::parse(line));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(where, Str("not a JSON record (", e.what(), ")"));
    }
  }
  return out;
}

}  // namespace mocap::pipeline
