#pragma once
// The object library (meshes/objects.yaml, schema in docs/objects.md): per object its mesh, unit,
// symmetries, tracker body with its marker layout, and the body-to-mesh transform. The simulator also
// reads each object's surface reflectivity (the ToF deformation of the paper's oil bottle).
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

struct ObjectSpec {
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
  void check(const std::string& where) const;
};

struct ObjectLibrary {
  std::vector<ObjectSpec> objects;
  /// Throws InputError naming `where` on duplicate ids/names or invalid entries.
  void check(const std::string& where) const;
  /// nullptr when absent.
  const ObjectSpec* Find(const std::string& name) const;
};

/// The library of the generated meshes (what meshes/objects.yaml holds).
ObjectLibrary DefaultObjectLibrary();
/// The camera's marker tool and the true camera mount T_cambody_camera of the default rig.
MarkerBody DefaultCameraBody();
Rigid3d DefaultCameraMount();

/// objects.yaml text for `library` (deterministic; numbers in metres and degrees).
std::string EncodeObjectsYaml(const ObjectLibrary& library);
/// Writes `text` to `path`; throws InputError on failure.
void WriteTextFile(const std::string& path, const std::string& text);

}  // namespace mocap::sim
