#pragma once
// Reading YAML files onto options structs (the only place YAML is read: DESIGN.md "Settings").
// Every error names the file and the line of the offending node.
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap::cli {

/// Parses a YAML file; throws InputError naming the file and line on a syntax error or a missing file.
YAML::Node LoadYamlFile(const std::filesystem::path& path);
/// "file:line" of a node (1-based line).
std::string Where(const std::filesystem::path& file, const YAML::Node& node);

/// node[key] as T; throws InputError naming file:line and the key when missing or of the wrong type.
template <typename T>
T Required(const std::filesystem::path& file, const YAML::Node& node, const std::string& key);
template <typename T>
T Optional(const std::filesystem::path& file, const YAML::Node& node, const std::string& key, const T& fallback);

Eigen::Vector3d Vector3(const std::filesystem::path& file, const YAML::Node& node);
/// {translation_m: [x, y, z], rotation_wxyz: [w, x, y, z]} or {translation_m, rvec_rad: [x, y, z]}.
Rigid3d Pose(const std::filesystem::path& file, const YAML::Node& node);
/// {width, height, fx, fy, cx, cy, dist: [k1, k2, p1, p2, k3, ...]}.
PinholeCamera Intrinsics(const std::filesystem::path& file, const YAML::Node& node);
/// "m", "cm" or "mm" to metres per unit.
double UnitScale(const std::filesystem::path& file, const YAML::Node& node);

}  // namespace mocap::cli
