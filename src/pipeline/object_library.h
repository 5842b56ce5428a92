#pragma once
// The object library (objects.yaml, schema in docs/objects.md): the one type every stage reads objects
// from. The labeller, the validator and the simulator each take a view of it (LabelObject,
// ValidationObject, sim::SimObject), derived here; objects.yaml has one reader and one writer, both here.
#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/rigid3.h"
#include "label/label_objects.h"
#include "render/renderer.h"
#include "session/import/bop_import.h"
#include "sim/sim_objects.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

/// A rotation that maps the object onto itself (mesh frame), as BOP's models_info.json has them.
struct ObjectSymmetry {
  enum class Type { kContinuous, kDiscrete } type = Type::kContinuous;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();     ///< unit
  Eigen::Vector3d offset_m = Eigen::Vector3d::Zero();  ///< a point on the axis
  double angle_deg = 0;                                 ///< discrete only; divides 360
};

/// The marker tool on an object, for the simulated tracker.
struct ObjectMarkers {
  std::vector<Eigen::Vector3d> markers_m;               ///< body frame, >= 3
  Eigen::Vector3d normal_body = Eigen::Vector3d::UnitZ();
};

struct LibraryObject {
  int id = 0;                       ///< 1..65535, unique (BOP obj_id; the class PNG value)
  std::string name;                 ///< unique
  std::string object_class;         ///< the name when not given
  std::string mesh;                 ///< as written: relative to the file's folder, or absolute
  std::filesystem::path mesh_path;  ///< absolute
  std::string unit = "m";           ///< m, cm or mm
  double unit_scale_to_m = 1.0;
  std::vector<ObjectSymmetry> symmetries;
  /// Tracker bodies carrying an instance each, with where the mesh sits on the body. Written as
  /// `tracker_body` + `T_body_mesh` for one, `tracker_bodies` (identity mounts) for several.
  std::vector<BodyMount> mounts;
  std::optional<ObjectMarkers> markers;       ///< simulation only
  double reflectivity = 0;                    ///< simulation only, 0..1
  double tof_deformation_m = 0;               ///< simulation only
  std::optional<BackFaceCulling> cull_back_faces;  ///< labeller override
  std::optional<double> diameter_m;           ///< BOP models_info diameter, when known
  /// Reflective: a time-of-flight camera's depth of it is pushed back along the ray, so the validator
  /// does not judge its range on such a camera (validate/label_check.h LeaveOutRange).
  bool tof_range_biased = false;
};

struct ObjectLibrary {
  std::filesystem::path file;  ///< where it was read from or will be written ("" for one built in memory)
  std::vector<LibraryObject> objects;
  const LibraryObject* Find(const std::string& name) const;
  const LibraryObject* FindId(int id) const;
  /// Throws InputError naming `where` for duplicate ids, names or bodies and invalid entries.
  void check(const std::string& where) const;
};

/// Reads objects.yaml: unknown keys, wrong types, a rotation that is not a rotation, a unit that is not
/// a unit and invalid values are InputErrors naming file:line and the key. Mesh paths resolve against
/// the file's folder.
ObjectLibrary ReadObjectLibrary(const std::filesystem::path& path);
ObjectLibrary ParseObjectLibrary(const std::string& text, const std::string& file_name,
                                 const std::filesystem::path& base_dir);

/// objects.yaml text (yaml-cpp's emitter; `comment` lines first). Mesh paths as in `mesh`.
std::string EmitObjectLibrary(const ObjectLibrary& library, const std::string& comment = "");
/// Writes `library` to `path` (atomically). Throws InputError on failure.
void WriteObjectLibrary(const ObjectLibrary& library, const std::filesystem::path& path, const std::string& comment = "");

/// The labeller's view.
std::vector<LabelObject> LabelObjectsOf(const ObjectLibrary& library);
/// The validator's view: each object compared modulo one declared symmetry (ChooseValidatorSymmetry).
std::vector<ValidationObject> ValidationObjectsOf(const ObjectLibrary& library);
/// The simulator's view; InputError naming the object when one has no markers or several mounts.
sim::SimObjects SimObjectsOf(const ObjectLibrary& library);
/// A library of the simulator's objects, meshes in `mesh_dir`, mesh paths written relative to
/// `yaml_dir` (where the file will live).
ObjectLibrary LibraryOfSimObjects(const sim::SimObjects& objects, const std::filesystem::path& mesh_dir,
                                  const std::filesystem::path& yaml_dir);

/// The objects of a BOP import (meshes in mm, identity mounts, one body per instance).
ObjectLibrary LibraryOfBopObjects(const std::vector<import::BopObject>& objects);
/// BopImportOptions::write_objects: the library above written with WriteObjectLibrary.
void WriteBopObjects(const std::filesystem::path& file, const std::vector<import::BopObject>& objects,
                     const std::string& source);

}  // namespace mocap::pipeline
