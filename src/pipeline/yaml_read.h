#pragma once
// Strict reading of the tool's YAML files (rig, object library, scenario): every error names the file,
// the line and the key. A key a map does not know is an error (a misspelt `T_body_camra:` must not
// silently leave the old calibration in place), with "did you mean" for a near miss.
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap::pipeline {

/// A parsed YAML document and the name errors use for it.
struct YamlDoc {
  std::string file;  ///< the path as given, or a name for text that came from elsewhere
  YAML::Node root;
  /// "file:line" of a node (1-based); the file alone when the node has no position.
  std::string Where(const YAML::Node& node) const;
};

/// Parses a file; InputError naming file:line for a syntax error, the file when it cannot be read.
YamlDoc LoadYaml(const std::filesystem::path& path);
YamlDoc ParseYaml(const std::string& text, const std::string& file);

/// The closest of `candidates` to `key` when it is a near miss (a typo), else "".
std::string NearestKey(std::string_view key, const std::vector<std::string>& candidates);

/// A map node whose keys are all known: constructing it throws for an unknown key (with "did you mean")
/// and for a node that is not a map. `what` names the map in messages ("camera 'kinect1'").
class YamlMap {
 public:
  YamlMap(const YamlDoc& doc, const YAML::Node& node, std::string what, std::initializer_list<const char*> keys);

  bool Has(const char* key) const { return static_cast<bool>(node_[key]); }
  YAML::Node operator[](const char* key) const { return node_[key]; }
  const YAML::Node& node() const { return node_; }
  const YamlDoc& doc() const { return *doc_; }
  std::string Where() const { return doc_->Where(node_); }
  std::string Where(const char* key) const { return doc_->Where(node_[key]); }

  /// Required field of type T (int, double, bool, std::string); numbers must be finite.
  template <typename T>
  T Get(const char* key) const;
  /// Optional field: `fallback` when absent.
  template <typename T>
  T Get(const char* key, const T& fallback) const;
  /// Throws "missing field 'key'" unless present.
  void Require(const char* key) const;
  /// An error about field `key`, at its line: "<file:line>: <what>: field 'key' <message>".
  [[noreturn]] void Fail(const char* key, const std::string& message) const;

 private:
  const YamlDoc* doc_;
  YAML::Node node_;
  std::string what_;
};

/// A scalar as T with file:line and `what` in the error (non-finite numbers refused).
template <typename T>
T As(const YamlDoc& doc, const YAML::Node& node, const std::string& what);

/// A list of exactly `count` finite numbers.
std::vector<double> Numbers(const YamlDoc& doc, const YAML::Node& node, size_t count, const std::string& what);
Eigen::Vector3d Vector3(const YamlDoc& doc, const YAML::Node& node, const std::string& what);

/// {translation_m: [x, y, z], rotation_wxyz: [w, x, y, z] | rvec_rad: [x, y, z]}. A quaternion whose
/// norm is not 1 (within 1e-3: often an xyzw list given as wxyz, or a typo) is not a rotation and an
/// error; `extra_keys` are further keys the caller reads from the same map.
Rigid3d Pose(const YamlDoc& doc, const YAML::Node& node, const std::string& what,
             std::initializer_list<const char*> extra_keys = {});
/// {width, height, fx, fy, cx, cy, dist: [k1, k2, p1, p2, k3, ...]} (OpenCV's model).
PinholeCamera Intrinsics(const YamlDoc& doc, const YAML::Node& node, const std::string& what);
/// A length unit: "m", "cm" or "mm", as metres per unit.
double LengthUnit(const YamlDoc& doc, const YAML::Node& node, const std::string& what);

}  // namespace mocap::pipeline
