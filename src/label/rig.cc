#include "label/rig.h"

#include <set>

#include "core/check.h"

namespace mocap {

void LabelRig::check(const std::string& where) const {
  std::set<std::string> seen;
  for (const LabelRigCamera& c : cameras) {
    if (c.camera.empty()) throw InputError(where, "a rig camera has no name");
    if (!seen.insert(c.camera).second) throw InputError(where, Str("camera '", c.camera, "' appears twice"));
    if (c.color_camera) c.color_camera->check();
    if (c.body && c.body->empty()) throw InputError(where, Str("camera '", c.camera, "': empty body name"));
  }
}

const LabelRigCamera* LabelRig::Find(const std::string& camera) const {
  for (const LabelRigCamera& c : cameras)
    if (c.camera == camera) return &c;
  return nullptr;
}

}  // namespace mocap
