#pragma once
// Writing the tool's YAML files with yaml-cpp's emitter. Numbers are written as the shortest decimal
// that reads back as the same double, so a file written and read again gives bit-identical values (a
// simulated rig's calibration labels exactly as the in-memory one did).
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap::pipeline {

/// The shortest round-trip decimal of `value` ("0.1", "1e-06", "3"); -0 is written as 0.
std::string ShortestDecimal(double value);

void EmitNumber(YAML::Emitter& out, double value);
void EmitVector(YAML::Emitter& out, const double* values, size_t count);
void EmitVector3(YAML::Emitter& out, const Eigen::Vector3d& v);
/// {translation_m, rotation_wxyz} (w >= 0).
void EmitPose(YAML::Emitter& out, const Rigid3d& pose);
void EmitIntrinsics(YAML::Emitter& out, const PinholeCamera& camera);

/// Writes `text` to `path` through a temporary file and a rename, so a reader never sees half a file.
/// Throws InputError naming the file.
void WriteTextAtomically(const std::filesystem::path& path, const std::string& text);

}  // namespace mocap::pipeline
