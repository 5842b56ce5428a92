#pragma once
// What the labeller needs to know of each object: its mesh, unit and the tracker bodies that carry it.
// Filled from meshes/objects.yaml or a session's own objects.yaml (src/cli/objects_yaml.cc).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/rigid3.h"
#include "render/renderer.h"

namespace mocap {

/// A tracker body carrying an object, and where the mesh sits on it.
struct BodyMount {
  std::string body;     ///< tracker body name in the session
  Rigid3d T_body_mesh;  ///< mesh coordinates (metres, after the unit) into the body frame
};

struct LabelObject {
  int id = 0;                          ///< the object's id (objects.yaml `id`; BOP `obj_id`), 1..65535
  std::string name;                    ///< unique
  std::string object_class;            ///< semantic class; the name when not given
  std::filesystem::path mesh_path;     ///< absolute
  double unit_scale_to_m = 1.0;        ///< mesh unit: 1 for metres, 0.001 for millimetres
  std::vector<BodyMount> mounts;       ///< one per instance; at least one
  /// objects.yaml `cull_back_faces`; unset: LabelOptions::renderer's choice (kAuto by default).
  std::optional<BackFaceCulling> back_face_culling = std::nullopt;
  /// Throws InputError naming `where` for an id out of range, an empty name or no mount.
  void check(const std::string& where) const;
};

/// Throws InputError on duplicate names, ids or bodies across objects, after checking each object.
void CheckLabelObjects(const std::vector<LabelObject>& objects, const std::string& where);

}  // namespace mocap
