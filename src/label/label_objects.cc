#include "label/label_objects.h"

#include <set>

#include "core/check.h"

namespace mocap {

void LabelObject::check(const std::string& where) const {
  if (name.empty()) throw InputError(where, "an object has no name");
  if (id < 1 || id > 65535) throw InputError(where, Str("object '", name, "': id ", id, " is outside 1..65535"));
  if (!(unit_scale_to_m > 0)) throw InputError(where, Str("object '", name, "': unit scale must be positive"));
  if (mounts.empty()) throw InputError(where, Str("object '", name, "' names no tracker body"));
  for (const BodyMount& m : mounts)
    if (m.body.empty()) throw InputError(where, Str("object '", name, "': empty tracker body name"));
}

void CheckLabelObjects(const std::vector<LabelObject>& objects, const std::string& where) {
  std::set<std::string> names, bodies;
  std::set<int> ids;
  for (const LabelObject& o : objects) {
    o.check(where);
    if (!names.insert(o.name).second) throw InputError(where, Str("object name '", o.name, "' appears twice"));
    if (!ids.insert(o.id).second) throw InputError(where, Str("object id ", o.id, " appears twice"));
    for (const BodyMount& m : o.mounts)
      if (!bodies.insert(m.body).second)
        throw InputError(where, Str("tracker body '", m.body, "' carries two objects"));
  }
}

}  // namespace mocap
