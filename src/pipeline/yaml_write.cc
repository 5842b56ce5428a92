#include "pipeline/yaml_write.h"

#include <charconv>
#include <fstream>

#include "core/check.h"

namespace mocap::pipeline {

std::string ShortestDecimal(double value) {
  MOCAP_CHECK(std::isfinite(value), "non-finite number written to YAML");
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value + 0.0);
  MOCAP_CHECK(result.ec == std::errc(), "to_chars failed");
  return std::string(buffer, result.ptr);
}

void EmitNumber(YAML::Emitter& out, double value) { out << ShortestDecimal(value); }

void EmitVector(YAML::Emitter& out, const double* values, size_t count) {
  out << YAML::Flow << YAML::BeginSeq;
  for (size_t i = 0; i < count; ++i) EmitNumber(out, values[i]);
  out << YAML::EndSeq;
}

void EmitVector3(YAML::Emitter& out, const Eigen::Vector3d& v) { EmitVector(out, v.data(), 3); }

void EmitPose(YAML::Emitter& out, const Rigid3d& pose) {
  const Eigen::Vector4d q = pose.quat_wxyz();
  out << YAML::BeginMap << YAML::Key << "translation_m" << YAML::Value;
  EmitVector3(out, pose.translation());
  out << YAML::Key << "rotation_wxyz" << YAML::Value;
  EmitVector(out, q.data(), 4);
  out << YAML::EndMap;
}

void EmitIntrinsics(YAML::Emitter& out, const PinholeCamera& c) {
  out << YAML::BeginMap;
  out << YAML::Key << "width" << YAML::Value << c.width << YAML::Key << "height" << YAML::Value << c.height;
  const std::pair<const char*, double> fields[] = {{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}};
  for (const auto& [key, value] : fields) {
    out << YAML::Key << key << YAML::Value;
    EmitNumber(out, value);
  }
  size_t used = c.dist.size();
  while (used > 5 && c.dist[used - 1] == 0) --used;  // k4..k6 only when the rational model is used
  out << YAML::Key << "dist" << YAML::Value;
  EmitVector(out, c.dist.data(), used);
  out << YAML::EndMap;
}

void WriteTextAtomically(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  {
    std::ofstream file(temporary, std::ios::trunc);
    if (!file) throw InputError(path.string(), "cannot open for writing (does the folder exist and is it writable?)");
    file << text;
    file.close();
    if (!file) {
      std::filesystem::remove(temporary);
      throw InputError(path.string(), "write failed (disk full?)");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) throw InputError(path.string(), Str("could not be put in place: ", error.message()));
}

}  // namespace mocap::pipeline
