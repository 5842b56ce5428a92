#pragma once
// Reading typed fields out of parsed JSON with errors that name the file, position and field.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "core/check.h"

namespace mocap::json_fields {

/// The member `key` of `object`; throws InputError(where, "missing field 'key'") when absent.
const nlohmann::json& Field(const nlohmann::json& object, const char* key, const std::string& where);

/// Typed accessors; each throws InputError naming `where` and `key` on absence or a wrong type.
int64_t Int(const nlohmann::json& object, const char* key, const std::string& where);
double Number(const nlohmann::json& object, const char* key, const std::string& where);
std::string String(const nlohmann::json& object, const char* key, const std::string& where);
bool Bool(const nlohmann::json& object, const char* key, const std::string& where);

/// Same, returning `fallback` when the field is absent (a wrong type still throws).
int64_t IntOr(const nlohmann::json& object, const char* key, int64_t fallback, const std::string& where);
double NumberOr(const nlohmann::json& object, const char* key, double fallback, const std::string& where);
std::string StringOr(const nlohmann::json& object, const char* key, const std::string& fallback,
                     const std::string& where);

}  // namespace mocap::json_fields
