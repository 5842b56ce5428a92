#pragma once
// `mocaplabel calibrate pivot` and `calibrate object-mount --pointer`: the NDI way to an object mount
// (calibrate/pivot.h) from recorded sessions. A pivot session: the pointer turning about its tip in a
// divot; gives the tip in the pointer body's frame (a pointer file). A landmarks session: the pointer
// resting on each landmark of the object in the landmarks file's order; gives T_body_mesh.
#include <string>

#include "calibrate/pivot.h"

namespace mocap::cli {

struct PointerArgs {
  std::string session;
  std::string pointer_body;   ///< pivot: the pointer's tracker body
  double from_s = 0, to_s = 0;  ///< pivot: seconds after the body's first sample; to_s 0 = the end
  std::string pointer, landmarks;  ///< object-mount: the pointer and landmarks files
  std::string object, objects;     ///< object-mount: the object; library (default: SESSION/objects.yaml)
  std::string out;
  bool force = false, json = false;
};

int CalibratePivotOfSession(const PointerArgs& args, const PivotOptions& options);
int CalibrateObjectMountFromPointer(const PointerArgs& args, const TouchOptions& options);

}  // namespace mocap::cli
