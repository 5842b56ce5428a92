#include "sim/mesh_generator.h"

#include <cmath>
#include <filesystem>
#include <numbers>

#include "core/check.h"
#include "sim/mesh_check.h"
#include "sim/sim_objects.h"
#include "sim/ply_writer.h"

namespace mocap::sim {
namespace {

constexpr Rgb8 kJugYellow{228, 186, 38};
constexpr Rgb8 kLabelBlue{30, 60, 140};
constexpr Rgb8 kBlack{25, 25, 28};
constexpr Rgb8 kFunnelBlue{40, 90, 200};
constexpr Rgb8 kCastIron{92, 98, 106};
constexpr Rgb8 kAluminium{165, 168, 172};
constexpr Rgb8 kValveRed{165, 32, 30};
constexpr Rgb8 kOilFilter{30, 70, 160};
constexpr Rgb8 kWood{156, 112, 70};
constexpr Rgb8 kSteel{70, 72, 76};
constexpr Rgb8 kSkin{222, 178, 148};

Rigid3d Translate(double x, double y, double z) { return Rigid3d(Eigen::Quaterniond::Identity(), {x, y, z}); }
/// Places a shell whose axis is its own z along the mesh's +x (or +y) axis, starting at `origin`.
Rigid3d AlongX(const Eigen::Vector3d& origin) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY())), origin);
}
Rigid3d AlongY(const Eigen::Vector3d& origin) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitX())), origin);
}

/// A cylinder with chamfered rims (more realistic shading, more triangles).
void AddChamferedCylinder(MeshBuilder& builder, double r, double length, double chamfer, int segments, Rgb8 color,
                          const Rigid3d& T_mesh_shell) {
  const double c = std::min(chamfer, 0.4 * std::min(r, length));
  builder.AddLathe({{0, 0, 0, 2, 0, 0, color},
                    {0, r - c, r - c, 2, 0, 0, color},
                    {c, r, r, 2, 0, 0, color},
                    {length - c, r, r, 2, 0, 0, color},
                    {length, r - c, r - c, 2, 0, 0, color},
                    {length, 0, 0, 2, 0, 0, color}},
                   segments, T_mesh_shell);
}

/// A rounded box as a superelliptic lathe from z0 to z1 with flat ends.
void AddRoundedBox(MeshBuilder& builder, double rx, double ry, double z0, double z1, double exponent, int segments,
                   Rgb8 color, const Rigid3d& T_mesh_shell = {}) {
  const double bevel = 0.006;
  builder.AddLathe({{z0, 0, 0, exponent, 0, 0, color},
                    {z0, rx - bevel, ry - bevel, exponent, 0, 0, color},
                    {z0 + bevel, rx, ry, exponent, 0, 0, color},
                    {z1 - bevel, rx, ry, exponent, 0, 0, color},
                    {z1, rx - bevel, ry - bevel, exponent, 0, 0, color},
                    {z1, 0, 0, exponent, 0, 0, color}},
                   segments, T_mesh_shell);
}

}  // namespace

ColoredMesh GenerateOilBottle() {
  MeshBuilder builder;
  // Body: rounded rectangle (superellipse n = 4) with a blue label band, tapering into an off-centre
  // spout at the front (+x), as on a 5-quart jug.
  auto ring = [](double z, double rx, double ry, double n, double cx, Rgb8 color) {
    return LatheRing{z, rx, ry, n, cx, 0, color};
  };
  builder.AddLathe({ring(0.000, 0.000, 0.000, 4, 0, kJugYellow),
                    ring(0.000, 0.078, 0.048, 4, 0, kJugYellow),
                    ring(0.006, 0.085, 0.055, 4, 0, kJugYellow),
                    ring(0.060, 0.085, 0.055, 4, 0, kJugYellow),
                    ring(0.061, 0.0852, 0.0552, 4, 0, kLabelBlue),
                    ring(0.150, 0.0852, 0.0552, 4, 0, kLabelBlue),
                    ring(0.151, 0.085, 0.055, 4, 0, kJugYellow),
                    ring(0.200, 0.085, 0.055, 4, 0, kJugYellow),
                    ring(0.215, 0.078, 0.051, 3.5, 0.008, kJugYellow),
                    ring(0.228, 0.060, 0.042, 3, 0.022, kJugYellow),
                    ring(0.238, 0.038, 0.031, 2.5, 0.036, kJugYellow),
                    ring(0.244, 0.022, 0.022, 2, 0.045, kJugYellow),
                    ring(0.252, 0.022, 0.022, 2, 0.045, kJugYellow),
                    ring(0.252, 0.000, 0.000, 2, 0.045, kJugYellow)},
                   96);
  // Cap on the spout.
  AddChamferedCylinder(builder, 0.0245, 0.030, 0.003, 64, kBlack, Translate(0.045, 0, 0.250));
  // Grip handle at the back: a closed loop in the xz plane, its inner leg inside the body.
  std::vector<Eigen::Vector3d> loop;
  const double x_out = -0.108, x_in = -0.060, z_low = 0.120, z_high = 0.232, corner = 0.02;
  const double centres[4][2] = {{x_in - corner, z_high - corner}, {x_out + corner, z_high - corner},
                                 {x_out + corner, z_low + corner}, {x_in - corner, z_low + corner}};
  for (int k = 0; k < 4; ++k) {
    for (int s = 0; s <= 6; ++s) {
      const double a = std::numbers::pi / 2 * (k + s / 6.0);
      loop.emplace_back(centres[k][0] + corner * std::cos(a), 0.0, centres[k][1] + corner * std::sin(a));
    }
  }
  builder.AddClosedTube(loop, 0.012, 24, kJugYellow);
  return builder.Take();
}

ColoredMesh GenerateFunnel() {
  MeshBuilder builder;
  // Closed (r, z) profile of a thin-walled funnel, revolved: a torus-like shell (spout open at the
  // bottom, cone open at the top), 2 mm walls and a rolled rim.
  const std::vector<std::pair<double, double>> profile = {
      {0.0090, 0.000}, {0.0110, 0.000}, {0.0120, 0.055}, {0.0730, 0.140}, {0.0760, 0.143},
      {0.0760, 0.150}, {0.0735, 0.150}, {0.0710, 0.143}, {0.0100, 0.057}};
  std::vector<LatheRing> rings;
  for (const auto& [r, z] : profile) rings.push_back({z, r, r, 2, 0, 0, kFunnelBlue});
  builder.AddLathe(rings, 96);
  return builder.Take();
}

ColoredMesh GenerateEngineBlock() {
  MeshBuilder builder;
  const int seg = 96;
  AddRoundedBox(builder, 0.180, 0.100, 0.000, 0.060, 8, seg, kSteel);          // oil pan
  AddRoundedBox(builder, 0.210, 0.130, 0.055, 0.210, 10, seg, kCastIron);     // block
  AddRoundedBox(builder, 0.205, 0.110, 0.205, 0.265, 10, seg, kAluminium);    // cylinder head
  builder.AddLathe({{0.262, 0, 0, 6, 0, 0, kValveRed},
                    {0.262, 0.195, 0.085, 6, 0, 0, kValveRed},
                    {0.280, 0.195, 0.085, 6, 0, 0, kValveRed},
                    {0.292, 0.185, 0.078, 6, 0, 0, kValveRed},
                    {0.298, 0.170, 0.066, 6, 0, 0, kValveRed},
                    {0.300, 0.000, 0.000, 6, 0, 0, kValveRed}},
                   2 * seg);                                                  // valve cover
  for (int i = 0; i < 4; ++i) {
    const double x = -0.135 + 0.09 * i;
    AddChamferedCylinder(builder, 0.011, 0.018, 0.002, seg / 2, kBlack, Translate(x, 0.0, 0.296));  // plug bosses
    AddChamferedCylinder(builder, 0.021, 0.030, 0.003, seg, kCastIron, AlongY({x, 0.105, 0.235}));   // exhaust
    AddChamferedCylinder(builder, 0.026, 0.025, 0.004, seg, kCastIron, AlongY({x, 0.110, 0.135}));   // bore bosses
  }
  AddChamferedCylinder(builder, 0.070, 0.022, 0.004, 2 * seg, kBlack, AlongX({0.205, 0.0, 0.105}));      // crank pulley
  AddChamferedCylinder(builder, 0.045, 0.018, 0.003, seg, kBlack, AlongX({0.200, -0.04, 0.232}));        // cam pulley
  AddChamferedCylinder(builder, 0.045, 0.090, 0.005, seg, kAluminium, AlongX({0.140, -0.10, 0.175}));    // alternator
  AddChamferedCylinder(builder, 0.034, 0.085, 0.004, seg, kOilFilter, AlongY({0.060, -0.185, 0.110}));   // oil filter
  AddChamferedCylinder(builder, 0.120, 0.020, 0.006, 2 * seg, kCastIron, AlongX({-0.225, 0.0, 0.135})); // bell housing
  AddChamferedCylinder(builder, 0.025, 0.040, 0.004, seg, kCastIron, AlongY({-0.100, -0.165, 0.150}));  // mount bosses
  AddChamferedCylinder(builder, 0.025, 0.040, 0.004, seg, kCastIron, AlongY({0.100, -0.165, 0.150}));
  return builder.Take();
}

ColoredMesh GenerateTable() {
  MeshBuilder builder;
  builder.AddBox({0.60, 0.40, 0.015}, kWood, Translate(0, 0, 0.735));
  for (int i = 0; i < 4; ++i) {
    const double x = (i & 1) ? 0.53 : -0.53, y = (i & 2) ? 0.33 : -0.33;
    builder.AddBox({0.025, 0.025, 0.361}, kSteel, Translate(x, y, 0.361));
  }
  return builder.Take();
}

ColoredMesh GenerateHand() {
  MeshBuilder builder;
  AddRoundedBox(builder, 0.050, 0.043, -0.014, 0.014, 4, 48, kSkin);  // palm
  for (int i = 0; i < 4; ++i) {
    const double y = -0.030 + 0.020 * i;
    const double length = (i == 0 || i == 3) ? 0.065 : 0.080;
    AddChamferedCylinder(builder, 0.009, length, 0.004, 24, kSkin, AlongX({0.040, y, 0.0}));
  }
  const Rigid3d thumb(Eigen::Quaterniond(Eigen::AngleAxisd(-std::numbers::pi / 4, Eigen::Vector3d::UnitZ()) *
                                         Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitY())),
                      Eigen::Vector3d(0.010, -0.040, 0.0));
  AddChamferedCylinder(builder, 0.011, 0.060, 0.004, 24, kSkin, thumb);
  return builder.Take();
}

std::vector<GeneratedMesh> GenerateAllMeshes() {
  std::vector<GeneratedMesh> meshes;
  meshes.push_back({"oil_bottle", GenerateOilBottle(), {0.205, 0.11, 0.28}});
  meshes.push_back({"funnel", GenerateFunnel(), {0.152, 0.152, 0.15}});
  meshes.push_back({"engine_block", GenerateEngineBlock(), {0.455, 0.32, 0.314}});
  meshes.push_back({"table", GenerateTable(), {1.2, 0.8, 0.75}});
  meshes.push_back({"hand", GenerateHand(), {0.17, 0.13, 0.028}});
  return meshes;
}

std::vector<std::string> WriteMeshLibrary(const std::string& out_dir) {
  std::error_code error;
  std::filesystem::create_directories(out_dir, error);
  if (error) throw InputError(out_dir, Str("cannot create the folder: ", error.message()));
  std::vector<std::string> written;
  for (const GeneratedMesh& generated : GenerateAllMeshes()) {
    const MeshTopologyReport report = CheckMeshTopology(generated.mesh);
    MOCAP_CHECK(report.watertight() && report.volume_m3 > 0, "generated mesh ", generated.name, " is not closed");
    const std::string path = (std::filesystem::path(out_dir) / (generated.name + ".ply")).string();
    WritePlyBinary(path, generated.mesh, Str("mocaplabel procedural model '", generated.name, "', unit: metre"));
    written.push_back(path);
  }
  return written;
}

}  // namespace mocap::sim
