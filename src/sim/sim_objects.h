#pragma once
// The simulator's view of the object library (pipeline/object_library.h derives it from objects.yaml;
// schema in docs/objects.md): per object its mesh, unit, symmetries, tracker body with its marker
// layout, the body-to-mesh transform, and its surface reflectivity (the ToF deformation of the paper's
// oil bottle). DefaultSimObjects() is the built-in library whose meshes `sim meshes` generates.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/rigid3.h"

namespace mocap::sim {

/// A passive marker tool: marker sphere centres in the body frame (metres) and the direction they face.
struct MarkerBody {
  std::string name;                         ///< tracker body name, e.g. "bottle_body"
  std::vector<Eigen::Vector3d> markers_m;   ///< body frame; at least 3 (NDI needs 3 to fit a pose)
  Eigen::Vector3d normal_body = Eigen::Vector3d::UnitZ();  ///< unit; the markers' facing direction
  void check(const std::string& where) const;
};

struct Symmetry {
  enum class Type { kContinuous, kDiscrete } type = Type::kContinuous;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit, mesh frame
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();  ///< a point on the axis, mesh frame
  double angle_deg = 0;  ///< discrete only: the rotation that maps the object onto itself
};

struct SimObject {
  int id = 0;                ///< instance label in masks (1..65535; 0 is background)
  std::string name;          ///< unique, e.g. "oil_bottle"
  std::string object_class;  ///< semantic class, e.g. "bottle"
  std::string mesh;          ///< file relative to the objects.yaml folder
  double unit_scale_to_m = 1.0;  ///< 1 for metres, 0.001 for millimetres
  std::vector<Symmetry> symmetries;
  MarkerBody body;
  Rigid3d T_body_mesh;       ///< maps mesh coordinates into the marker body frame
  double reflectivity = 0;   ///< 0 matte .. 1 mirror-like; drives the ToF deformation
  double tof_deformation_m = 0;  ///< largest extra ToF path (metres) at grazing incidence when reflective
  /// What its objects.yaml declares for the validator (not read by the simulation): the object is known
  /// to be reflective, as a user knows a shiny bottle (pipeline/object_library.h).
  bool tof_range_biased = false;
  void check(const std::string& where) const;
};

struct SimObjects {
  std::vector<SimObject> objects;
  /// Throws InputError naming `where` on duplicate ids/names or invalid entries.
  void check(const std::string& where) const;
  /// nullptr when absent.
  const SimObject* Find(const std::string& name) const;
};

/// The library of the generated meshes (what meshes/objects.yaml holds).
SimObjects DefaultSimObjects();
/// The camera's marker tool and the true camera mount T_cambody_camera of the default rig.
MarkerBody DefaultCameraBody();
Rigid3d DefaultCameraMount();


}  // namespace mocap::sim
