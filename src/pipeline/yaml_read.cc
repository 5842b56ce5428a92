#include "pipeline/yaml_read.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/check.h"

namespace mocap::pipeline {
namespace {

/// Levenshtein distance, case-insensitive (a key typed in the wrong case is a near miss too).
size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      const size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

std::string TypeName(const std::type_info& type) {
  if (type == typeid(int) || type == typeid(int64_t) || type == typeid(uint64_t)) return "an integer";
  if (type == typeid(double)) return "a number";
  if (type == typeid(bool)) return "true or false";
  return "a string";
}

}  // namespace

std::string YamlDoc::Where(const YAML::Node& node) const {
  if (!node.IsDefined() || node.Mark().is_null()) return file;
  return Str(file, ":", node.Mark().line + 1);
}

YamlDoc ParseYaml(const std::string& text, const std::string& file) {
  try {
    return {file, YAML::Load(text)};
  } catch (const YAML::Exception& e) {
    throw InputError(Str(file, ":", e.mark.line + 1), Str("not valid YAML: ", e.msg));
  }
}

YamlDoc LoadYaml(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in || std::filesystem::is_directory(path))
    throw InputError(path.string(), "cannot be read (does the file exist?)");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseYaml(text.str(), path.string());
}

std::string NearestKey(std::string_view key, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, key.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const size_t d = EditDistance(key, c);
    if (d < best_distance) best_distance = d, best = c;
  }
  return best;
}

YamlMap::YamlMap(const YamlDoc& doc, const YAML::Node& node, std::string what, std::initializer_list<const char*> keys)
    : doc_(&doc), node_(node), what_(std::move(what)) {
  if (!node.IsMap()) throw InputError(doc.Where(node), Str(what_, " must be a map of 'key: value' fields"));
  const std::vector<std::string> known(keys.begin(), keys.end());
  for (const auto& item : node) {
    const std::string key = item.first.Scalar();
    if (std::find(known.begin(), known.end(), key) != known.end()) continue;
    const std::string near = NearestKey(key, known);
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError(doc.Where(item.first),
                     Str("unknown key '", key, "' in ", what_,
                         near.empty() ? Str(" (known keys: ", list, ")") : Str(" (did you mean '", near, "'?)")));
  }
}

void YamlMap::Require(const char* key) const {
  if (!node_[key]) throw InputError(Where(), Str(what_, ": missing field '", key, "'"));
}

void YamlMap::Fail(const char* key, const std::string& message) const {
  throw InputError(Where(key), Str(what_, ": field '", key, "' ", message));
}

template <typename T>
T As(const YamlDoc& doc, const YAML::Node& node, const std::string& what) {
  T value{};
  bool ok = node.IsScalar();
  if (ok) {
    try {
      value = node.as<T>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
  }
  if (!ok) throw InputError(doc.Where(node), Str("'", what, "' must be ", TypeName(typeid(T)),
                                                 node.IsScalar() ? Str(" (got '", node.Scalar(), "')") : ""));
  if constexpr (std::is_floating_point_v<T>)
    if (!std::isfinite(value)) throw InputError(doc.Where(node), Str("'", what, "' must be a finite number"));
  return value;
}

template <typename T>
T YamlMap::Get(const char* key) const {
  Require(key);
  return As<T>(*doc_, node_[key], key);
}

template <typename T>
T YamlMap::Get(const char* key, const T& fallback) const {
  return Has(key) ? As<T>(*doc_, node_[key], key) : fallback;
}

#define MOCAP_YAML_INSTANTIATE(T)                                                    \
  template T As<T>(const YamlDoc&, const YAML::Node&, const std::string&);          \
  template T YamlMap::Get<T>(const char*) const;                                    \
  template T YamlMap::Get<T>(const char*, const T&) const;
MOCAP_YAML_INSTANTIATE(int)
MOCAP_YAML_INSTANTIATE(int64_t)
MOCAP_YAML_INSTANTIATE(uint64_t)
MOCAP_YAML_INSTANTIATE(double)
MOCAP_YAML_INSTANTIATE(bool)
MOCAP_YAML_INSTANTIATE(std::string)
#undef MOCAP_YAML_INSTANTIATE

std::vector<double> Numbers(const YamlDoc& doc, const YAML::Node& node, size_t count, const std::string& what) {
  if (!node.IsSequence() || node.size() != count)
    throw InputError(doc.Where(node), Str("'", what, "' must be a list of ", count, " numbers"));
  std::vector<double> out;
  for (const auto& item : node) out.push_back(As<double>(doc, item, what));
  return out;
}

Eigen::Vector3d Vector3(const YamlDoc& doc, const YAML::Node& node, const std::string& what) {
  const auto v = Numbers(doc, node, 3, what);
  return {v[0], v[1], v[2]};
}

Rigid3d Pose(const YamlDoc& doc, const YAML::Node& node, const std::string& what,
             std::initializer_list<const char*> extra_keys) {
  std::vector<const char*> keys{"translation_m", "rotation_wxyz", "rvec_rad"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  if (!node.IsMap()) throw InputError(doc.Where(node), Str("'", what, "' must be a pose {translation_m, rotation_wxyz | rvec_rad}"));
  for (const auto& item : node) {
    const std::string key = item.first.Scalar();
    if (std::find_if(keys.begin(), keys.end(), [&](const char* k) { return key == k; }) != keys.end()) continue;
    const std::string near = NearestKey(key, {keys.begin(), keys.end()});
    throw InputError(doc.Where(item.first), Str("unknown key '", key, "' in pose '", what, "'",
                                                near.empty() ? "" : Str(" (did you mean '", near, "'?)")));
  }
  if (!node["translation_m"]) throw InputError(doc.Where(node), Str("pose '", what, "' has no 'translation_m'"));
  const Eigen::Vector3d t = Vector3(doc, node["translation_m"], "translation_m");
  if (node["rvec_rad"] && node["rotation_wxyz"])
    throw InputError(doc.Where(node), Str("pose '", what, "': give rotation_wxyz or rvec_rad, not both"));
  if (node["rvec_rad"]) return Rigid3d::FromRvec(Vector3(doc, node["rvec_rad"], "rvec_rad"), t);
  if (!node["rotation_wxyz"]) throw InputError(doc.Where(node), Str("pose '", what, "' has no 'rotation_wxyz' or 'rvec_rad'"));
  const auto q = Numbers(doc, node["rotation_wxyz"], 4, "rotation_wxyz");
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-3)
    throw InputError(doc.Where(node["rotation_wxyz"]),
                     Str("'rotation_wxyz' of '", what, "' is not a rotation: quaternion norm ", norm,
                         " is not 1 (the order is w x y z)"));
  return Rigid3d::FromQuatWxyz(q[0], q[1], q[2], q[3], t);
}

PinholeCamera Intrinsics(const YamlDoc& doc, const YAML::Node& node, const std::string& what) {
  const YamlMap map(doc, node, what, {"width", "height", "fx", "fy", "cx", "cy", "dist"});
  PinholeCamera c;
  c.width = map.Get<int>("width");
  c.height = map.Get<int>("height");
  c.fx = map.Get<double>("fx");
  c.fy = map.Get<double>("fy");
  c.cx = map.Get<double>("cx");
  c.cy = map.Get<double>("cy");
  if (map.Has("dist")) {
    const YAML::Node d = map["dist"];
    if (!d.IsSequence() || d.size() > 8) map.Fail("dist", "must list at most 8 coefficients (k1 k2 p1 p2 k3 k4 k5 k6)");
    for (size_t i = 0; i < d.size(); ++i) c.dist[i] = As<double>(doc, d[i], "dist");
  }
  try {
    c.check();
  } catch (const InputError& e) {
    throw InputError(map.Where(), Str(what, ": ", e.what()));
  }
  return c;
}

double LengthUnit(const YamlDoc& doc, const YAML::Node& node, const std::string& what) {
  const std::string unit = As<std::string>(doc, node, what);
  if (unit == "m") return 1.0;
  if (unit == "cm") return 0.01;
  if (unit == "mm") return 0.001;
  throw InputError(doc.Where(node), Str("'", what, "': '", unit, "' is not a length unit (m, cm or mm)"));
}

}  // namespace mocap::pipeline
