#include "sim/sim_objects.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <set>
#include <sstream>

#include "core/check.h"

namespace mocap::sim {
namespace {

/// T_mesh_body from where the tool sits on the mesh, the direction its markers face (mesh frame) and
/// a twist of the tool about that direction.
Rigid3d MountOnMesh(const Eigen::Vector3d& position_mesh_m, const Eigen::Vector3d& facing_mesh, double twist_deg) {
  const Eigen::Quaterniond tilt = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), facing_mesh.normalized());
  const Eigen::Quaterniond twist(Eigen::AngleAxisd(RadFromDeg(twist_deg), Eigen::Vector3d::UnitZ()));
  return Rigid3d(tilt * twist, position_mesh_m);
}

/// A planar four-marker tool (marker plane z = 0, facing +z), coordinates in millimetres.
MarkerBody PlanarTool(const std::string& name, std::initializer_list<std::array<double, 2>> markers_mm) {
  MarkerBody body;
  body.name = name;
  for (const auto& m : markers_mm) body.markers_m.emplace_back(m[0] * 1e-3, m[1] * 1e-3, 0.0);
  return body;
}

SimObject NamedObject(int id, const std::string& name, const std::string& object_class, const std::string& mesh) {
  SimObject object;
  object.id = id;
  object.name = name;
  object.object_class = object_class;
  object.mesh = mesh;
  return object;
}

}  // namespace

void MarkerBody::check(const std::string& where) const {
  if (name.empty()) throw InputError(where, "tracker body without a name");
  if (markers_m.size() < 3) throw InputError(where, Str("tracker body '", name, "' has ", markers_m.size(), " markers; a pose needs at least 3"));
  if (std::abs(normal_body.norm() - 1.0) > 1e-6) throw InputError(where, Str("tracker body '", name, "': marker normal is not a unit vector"));
  for (size_t i = 0; i < markers_m.size(); ++i)
    for (size_t j = i + 1; j < markers_m.size(); ++j)
      if ((markers_m[i] - markers_m[j]).norm() < 0.01)
        throw InputError(where, Str("tracker body '", name, "': markers ", i, " and ", j, " are closer than 10 mm"));
}

void SimObject::check(const std::string& where) const {
  if (id < 1 || id > 65535) throw InputError(where, Str("object '", name, "': id ", id, " is outside 1..65535"));
  if (name.empty() || mesh.empty()) throw InputError(where, "object without a name or a mesh");
  if (!(unit_scale_to_m > 0)) throw InputError(where, Str("object '", name, "': unit scale must be positive"));
  if (reflectivity < 0 || reflectivity > 1) throw InputError(where, Str("object '", name, "': reflectivity outside [0, 1]"));
  if (tof_deformation_m < 0 || tof_deformation_m > 0.2)
    throw InputError(where, Str("object '", name, "': tof_deformation_m outside [0, 0.2]"));
  body.check(where);
}

void SimObjects::check(const std::string& where) const {
  std::set<int> ids;
  std::set<std::string> names;
  for (const SimObject& object : objects) {
    object.check(where);
    if (!ids.insert(object.id).second) throw InputError(where, Str("duplicate object id ", object.id));
    if (!names.insert(object.name).second) throw InputError(where, Str("duplicate object name '", object.name, "'"));
  }
}

const SimObject* SimObjects::Find(const std::string& name) const {
  for (const SimObject& object : objects)
    if (object.name == name) return &object;
  return nullptr;
}

SimObjects DefaultSimObjects() {
  SimObjects library;
  // Marker layouts: planar, four markers, all inter-marker distances distinct (>= 2.5 mm apart) and
  // different between tools, as NDI passive tool definitions require to tell tools apart.
  SimObject bottle = NamedObject(1, "oil_bottle", "bottle", "oil_bottle.ply");
  bottle.body = PlanarTool("bottle_body", {{0, 0}, {60, 0}, {25, 70}, {-30, 40}});
  // Tool on the +y side face of the jug, tilted 37 degrees upwards.
  bottle.T_body_mesh = MountOnMesh({-0.010, 0.062, 0.165}, {0, 0.8, 0.6}, 20).inverse();
  bottle.reflectivity = 0.8;
  bottle.tof_deformation_m = 0.03;
  bottle.tof_range_biased = true;  // the SegICP paper's shiny oil bottle, declared as a user would

  SimObject funnel = NamedObject(2, "funnel", "funnel", "funnel.ply");
  funnel.symmetries.push_back({Symmetry::Type::kContinuous, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 0});
  funnel.body = PlanarTool("funnel_body", {{0, 0}, {55, 0}, {-20, 71}, {54, 35}});
  // Tool on the outer cone wall, facing along the wall's outward normal.
  funnel.T_body_mesh = MountOnMesh({0.050, 0.0, 0.115}, {0.81, 0, -0.58}, -15).inverse();
  funnel.reflectivity = 0.1;

  SimObject engine = NamedObject(3, "engine_block", "engine", "engine_block.ply");
  engine.body = PlanarTool("engine_body", {{0, 0}, {80, 0}, {35, 62}, {-20, 88}});
  // Tool on a bracket over the front of the valve cover, tilted towards the front.
  engine.T_body_mesh = MountOnMesh({0.120, 0.040, 0.320}, {0.5, 0, 0.866}, 35).inverse();
  engine.reflectivity = 0.2;

  SimObject table = NamedObject(4, "table", "table", "table.ply");
  table.symmetries.push_back({Symmetry::Type::kDiscrete, Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 180});
  table.body = PlanarTool("table_body", {{0, 0}, {90, 0}, {20, 75}, {-40, 30}});
  // Tool on the corner of the table top nearest the tracker (as in the paper's set-up), facing up.
  table.T_body_mesh = MountOnMesh({-0.560, 0.360, 0.752}, {0, 0, 1}, 45).inverse();

  library.objects = {bottle, funnel, engine, table};
  return library;
}

MarkerBody DefaultCameraBody() {
  // The camera carries the largest tool (about 15 x 19 cm): its rotation noise is multiplied by the
  // camera-to-object distance (~1 m) in every label, so it dominates the label error. With the 5 x 6 cm
  // layout of the object tools the default scene's median label error was 2.0 mm at 0.15 mm marker
  // noise; with this one it is 0.8 mm (docs/simulation.md "Recording").
  return PlanarTool("camera_body", {{0, 0}, {150, 0}, {45, 186}, {-105, 135}});
}

Rigid3d DefaultCameraMount() {
  // The tool sits 6 cm above and 3 cm behind the RGB optical centre, facing up and forwards (optical
  // frame: y down, z forward), twisted by 10 degrees: T_cambody_camera is its inverse.
  return MountOnMesh({0.015, -0.060, -0.030}, {0, -0.8, 0.6}, 10).inverse();
}

}  // namespace mocap::sim
