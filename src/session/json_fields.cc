#include "session/json_fields.h"

namespace mocap::json_fields {
namespace {

[[noreturn]] void WrongType(const char* key, const char* expected, const nlohmann::json& value,
                            const std::string& where) {
  throw InputError(where, Str("field '", key, "' should be ", expected, ", found ", value.type_name()));
}

}  // namespace

const nlohmann::json& Field(const nlohmann::json& object, const char* key, const std::string& where) {
  if (!object.is_object()) throw InputError(where, Str("expected a JSON object holding '", key, "'"));
  const auto it = object.find(key);
  if (it == object.end()) throw InputError(where, Str("missing field '", key, "'"));
  return *it;
}

int64_t Int(const nlohmann::json& object, const char* key, const std::string& where) {
  const auto& value = Field(object, key, where);
  if (!value.is_number_integer()) WrongType(key, "an integer", value, where);
  return value.get<int64_t>();
}

double Number(const nlohmann::json& object, const char* key, const std::string& where) {
  const auto& value = Field(object, key, where);
  if (!value.is_number()) WrongType(key, "a number", value, where);
  return value.get<double>();
}

std::string String(const nlohmann::json& object, const char* key, const std::string& where) {
  const auto& value = Field(object, key, where);
  if (!value.is_string()) WrongType(key, "a string", value, where);
  return value.get<std::string>();
}

bool Bool(const nlohmann::json& object, const char* key, const std::string& where) {
  const auto& value = Field(object, key, where);
  if (!value.is_boolean()) WrongType(key, "true or false", value, where);
  return value.get<bool>();
}

int64_t IntOr(const nlohmann::json& object, const char* key, int64_t fallback, const std::string& where) {
  return object.is_object() && object.contains(key) ? Int(object, key, where) : fallback;
}

double NumberOr(const nlohmann::json& object, const char* key, double fallback, const std::string& where) {
  return object.is_object() && object.contains(key) ? Number(object, key, where) : fallback;
}

std::string StringOr(const nlohmann::json& object, const char* key, const std::string& fallback,
                     const std::string& where) {
  return object.is_object() && object.contains(key) ? String(object, key, where) : fallback;
}

}  // namespace mocap::json_fields
