// models/ of a BOP dataset (formats.md §1 models_info.json; bop_toolkit misc.calc_pts_diameter): every
// object of the library as obj_OOOOOO.ply in millimetres, with its diameter, extents and symmetries.
#include <Eigen/Geometry>
#include <algorithm>

#include "core/check.h"
#include "core/text.h"
#include "exporters/bop/bop_internal.h"
#include "render/mesh.h"
#include "session/durable_file.h"
#include "sim/ply_writer.h"

namespace mocap::exporters::bop {
namespace fs = std::filesystem;
namespace {

/// The largest distance between two vertices (BOP's diameter), exact. Only vertices far enough from the
/// centroid can belong to a pair longer than the best found so far, which prunes most of the O(n^2).
double DiameterM(const std::vector<Eigen::Vector3f>& points) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p.cast<double>();
  centroid /= static_cast<double>(points.size());
  std::vector<std::pair<double, Eigen::Vector3d>> by_radius;
  for (const auto& p : points) by_radius.emplace_back((p.cast<double>() - centroid).norm(), p.cast<double>());
  std::sort(by_radius.begin(), by_radius.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  double best = 0;
  for (size_t i = 0; i < by_radius.size(); ++i) {
    if (2.0 * by_radius[i].first < best) break;  // sorted: no later pair can reach `best`
    for (size_t j = i + 1; j < by_radius.size(); ++j) {
      if (by_radius[i].first + by_radius[j].first < best) break;
      best = std::max(best, (by_radius[i].second - by_radius[j].second).norm());
    }
  }
  return best;
}

/// A rotation by `angle_deg` about the symmetry axis through its offset, as a 4x4 in mm (row-major).
std::vector<double> SymmetryMatrixMm(const pipeline::ObjectSymmetry& s, double angle_deg) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle_deg * M_PI / 180.0, s.axis.normalized()).toRotationMatrix();
  const Eigen::Vector3d t_mm = (s.offset_m - R * s.offset_m) * 1e3;
  std::vector<double> out;
  for (int r = 0; r < 3; ++r) out.insert(out.end(), {R(r, 0), R(r, 1), R(r, 2), t_mm(r)});
  out.insert(out.end(), {0.0, 0.0, 0.0, 1.0});
  return out;
}

nlohmann::json ModelInfo(const pipeline::LibraryObject& object, const Mesh& mesh) {
  const Eigen::Vector3d min_mm = mesh.min_m().cast<double>() * 1e3, size_mm = (mesh.max_m() - mesh.min_m()).cast<double>() * 1e3;
  const double diameter_m = object.diameter_m ? *object.diameter_m : DiameterM(mesh.positions_m);
  nlohmann::json info = {{"diameter", diameter_m * 1e3}, {"min_x", min_mm.x()},  {"min_y", min_mm.y()},
                         {"min_z", min_mm.z()},          {"size_x", size_mm.x()}, {"size_y", size_mm.y()},
                         {"size_z", size_mm.z()}};
  for (const pipeline::ObjectSymmetry& s : object.symmetries) {
    if (s.type == pipeline::ObjectSymmetry::Type::kContinuous) {
      info["symmetries_continuous"].push_back({{"axis", {s.axis.x(), s.axis.y(), s.axis.z()}},
                                               {"offset", {s.offset_m.x() * 1e3, s.offset_m.y() * 1e3, s.offset_m.z() * 1e3}}});
      continue;
    }
    for (double angle = s.angle_deg; angle < 360.0 - 1e-9; angle += s.angle_deg)
      info["symmetries_discrete"].push_back(SymmetryMatrixMm(s, angle));
  }
  return info;
}

/// The mesh in mm: a PLY already in mm is placed as it is (its colours, texture and normals kept);
/// anything else is written as binary PLY from the loaded geometry and vertex colours.
void WriteModel(const pipeline::LibraryObject& object, const Mesh& mesh, const fs::path& file) {
  if (LowerExtension(object.mesh_path) == ".ply" && object.unit == "mm") {
    LinkOrCopyFile(object.mesh_path, file);
    return;
  }
  sim::ColoredMesh out;
  for (size_t i = 0; i < mesh.positions_m.size(); ++i) {
    out.positions_m.push_back(mesh.positions_m[i].cast<double>() * 1e3);  // millimetres, despite the field name
    const Eigen::Vector4f c = mesh.colors.empty() ? Eigen::Vector4f(0.7f, 0.7f, 0.7f, 1.0f) : mesh.colors[i];
    out.colors.push_back({static_cast<uint8_t>(c.x() * 255.0f + 0.5f), static_cast<uint8_t>(c.y() * 255.0f + 0.5f),
                          static_cast<uint8_t>(c.z() * 255.0f + 0.5f)});
  }
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
    out.triangles.push_back({mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]});
  sim::WritePlyBinary(file.string(), out, Str("mocaplabel export: ", object.name, ", millimetres"));
}

}  // namespace

int64_t WriteBopModels(const Dataset& dataset, const fs::path& models_dir, std::vector<std::string>& notes) {
  fs::create_directories(models_dir);
  std::map<int, nlohmann::json> info;
  for (const pipeline::LibraryObject& object : dataset.objects.objects) {
    const Mesh mesh = LoadMesh(object.mesh_path.string(), object.unit_scale_to_m);
    char name[32];
    std::snprintf(name, sizeof name, "obj_%06d.ply", object.id);
    WriteModel(object, mesh, models_dir / name);
    info[object.id] = ModelInfo(object, mesh);
  }
  WriteFileAtomically(models_dir / "models_info.json", BopJsonText(info));
  if (dataset.objects.objects.empty()) notes.push_back("no objects: models/ is empty");
  return static_cast<int64_t>(dataset.objects.objects.size()) + 1;
}

}  // namespace mocap::exporters::bop
