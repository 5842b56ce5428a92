#pragma once
// The pointer file (`calibrate pivot` writes it, `calibrate object-mount --pointer` reads it) and the
// landmarks file (where a lab lists the points of a mesh the pointer touches); docs/calibration.md
// "The pointer". Strict: unknown keys, wrong types and invalid values are errors naming file:line.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace mocap::cli {

/// A tracked pointer: its tracker body and its tip in that body's frame.
struct PointerTool {
  std::string body;
  Eigen::Vector3d tip_m = Eigen::Vector3d::Zero();
};

PointerTool ReadPointerFile(const std::filesystem::path& path);
PointerTool ParsePointer(const std::string& text, const std::string& file_name);
/// Written atomically; `comment` (provenance) becomes the first line.
void WritePointerFile(const PointerTool& pointer, const std::filesystem::path& path, const std::string& comment);

/// Points of an object's mesh, in the order the pointer touches them; metres in the mesh's frame
/// (converted from the file's `unit`).
struct Landmarks {
  std::vector<std::string> names;
  std::vector<Eigen::Vector3d> p_mesh_m;
};

Landmarks ReadLandmarksFile(const std::filesystem::path& path);
Landmarks ParseLandmarks(const std::string& text, const std::string& file_name);

}  // namespace mocap::cli
