#include "cli/yaml_util.h"

#include <vector>

#include "core/check.h"

namespace mocap::cli {

YAML::Node LoadYamlFile(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) throw InputError(path.string(), "no such file");
  try {
    return YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    throw InputError(Str(path.string(), ":", e.mark.line + 1), Str("not valid YAML: ", e.msg));
  }
}

std::string Where(const std::filesystem::path& file, const YAML::Node& node) {
  return node.Mark().is_null() ? file.string() : Str(file.string(), ":", node.Mark().line + 1);
}

template <typename T>
T Required(const std::filesystem::path& file, const YAML::Node& node, const std::string& key) {
  const YAML::Node value = node[key];
  if (!value) throw InputError(Where(file, node), Str("missing field '", key, "'"));
  try {
    return value.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(Where(file, value), Str("field '", key, "' has the wrong type"));
  }
}

template <typename T>
T Optional(const std::filesystem::path& file, const YAML::Node& node, const std::string& key, const T& fallback) {
  return node[key] ? Required<T>(file, node, key) : fallback;
}

template int Required<int>(const std::filesystem::path&, const YAML::Node&, const std::string&);
template double Required<double>(const std::filesystem::path&, const YAML::Node&, const std::string&);
template std::string Required<std::string>(const std::filesystem::path&, const YAML::Node&, const std::string&);
template int Optional<int>(const std::filesystem::path&, const YAML::Node&, const std::string&, const int&);
template double Optional<double>(const std::filesystem::path&, const YAML::Node&, const std::string&, const double&);
template std::string Optional<std::string>(const std::filesystem::path&, const YAML::Node&, const std::string&,
                                           const std::string&);

namespace {

std::vector<double> Numbers(const std::filesystem::path& file, const YAML::Node& node, size_t count) {
  if (!node.IsSequence() || node.size() != count)
    throw InputError(Where(file, node), Str("expected a list of ", count, " numbers"));
  std::vector<double> out;
  try {
    for (const auto& e : node) out.push_back(e.as<double>());
  } catch (const YAML::Exception&) {
    throw InputError(Where(file, node), "expected numbers");
  }
  return out;
}

}  // namespace

Eigen::Vector3d Vector3(const std::filesystem::path& file, const YAML::Node& node) {
  const auto v = Numbers(file, node, 3);
  return {v[0], v[1], v[2]};
}

Rigid3d Pose(const std::filesystem::path& file, const YAML::Node& node) {
  if (!node.IsMap()) throw InputError(Where(file, node), "expected a pose {translation_m, rotation_wxyz | rvec_rad}");
  if (!node["translation_m"]) throw InputError(Where(file, node), "pose without 'translation_m'");
  const Eigen::Vector3d t = Vector3(file, node["translation_m"]);
  if (node["rvec_rad"]) return Rigid3d::FromRvec(Vector3(file, node["rvec_rad"]), t);
  if (!node["rotation_wxyz"]) throw InputError(Where(file, node), "pose without 'rotation_wxyz' or 'rvec_rad'");
  const auto q = Numbers(file, node["rotation_wxyz"], 4);
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-3)
    throw InputError(Where(file, node["rotation_wxyz"]), Str("quaternion norm ", norm, " is not 1 (order is w x y z)"));
  return Rigid3d::FromQuatWxyz(q[0], q[1], q[2], q[3], t);
}

PinholeCamera Intrinsics(const std::filesystem::path& file, const YAML::Node& node) {
  PinholeCamera c;
  c.width = Required<int>(file, node, "width");
  c.height = Required<int>(file, node, "height");
  c.fx = Required<double>(file, node, "fx");
  c.fy = Required<double>(file, node, "fy");
  c.cx = Required<double>(file, node, "cx");
  c.cy = Required<double>(file, node, "cy");
  if (const YAML::Node d = node["dist"]) {
    if (!d.IsSequence() || d.size() > 8) throw InputError(Where(file, d), "'dist' must list at most 8 coefficients");
    for (size_t i = 0; i < d.size(); ++i) c.dist[i] = d[i].as<double>();
  }
  try {
    c.check();
  } catch (const InputError& e) {
    throw InputError(Where(file, node), e.what());
  }
  return c;
}

double UnitScale(const std::filesystem::path& file, const YAML::Node& node) {
  const std::string unit = node.as<std::string>();
  if (unit == "m") return 1.0;
  if (unit == "cm") return 0.01;
  if (unit == "mm") return 0.001;
  throw InputError(Where(file, node), Str("unknown unit '", unit, "' (m, cm or mm)"));
}

}  // namespace mocap::cli
