#pragma once
// `mocaplabel import bop`: a BOP scene into a session whose object poses are known per frame, so BOP
// data can be re-labelled (masks, visibility, exports) by the same pipeline as recorded sessions.
//
//  - Only frames whose colour image exists are imported (BOP releases often ship a subset of images).
//  - Camera "bop": intrinsics from scene_camera.json cam_K, depth_unit_m = depth_scale mm / 1000.
//    BOP allows cam_K (and depth_scale) to change per image; frames are then grouped by identical
//    values into cameras "bop", "bop_1", "bop_2", ... each with its own tracker, so that every camera
//    stream keeps a single, exact camera model.
//  - Tracker "objects" (frame "camera:bop"): one body per object instance, "obj_<obj_id:06d>" for the
//    first instance of an object in a frame and "obj_<obj_id:06d>_inst<k>" for the k-th further one
//    (BOP does not track identities across images: instance k is the k-th annotation of that object in
//    each frame). Each frame writes a sample for every body: valid with T_camera_object (metres) where
//    annotated, missing where not.
//  - Stamps are synthetic: stamp_ns = im_id / 30 Hz; source_id = the im_id; record.frame = im_id.
//  - objects.yaml in the session lists each object: id (BOP obj_id), name, mesh (absolute path), unit mm,
//    diameter, and the bodies that carry it (T_body_mesh = identity: BOP poses are of the model frame);
//    the same list is in manifest.extra["objects"].
#include <filesystem>
#include <functional>
#include <vector>
#include <string>

#include "core/progress.h"
#include "session/import/import_common.h"

namespace mocap::import {

/// An object of the imported scene, as objects.yaml will list it.
struct BopObject {
  int id = 0;                          ///< BOP obj_id
  std::string name;                    ///< obj_NNNNNN
  std::filesystem::path mesh;          ///< absolute; in millimetres
  double diameter_m = 0;
  std::vector<std::string> bodies;     ///< one tracker body per instance, mounted at identity
};

struct BopImportOptions {
  double frame_rate_hz = 30.0;  ///< synthetic rate turning im_id into stamps
  std::string software_version;
  ProgressSink* progress = nullptr;  ///< frames (bodies) written / total; not owned, may be null
  /// Writes the session's objects.yaml (the pipeline's writer, pipeline/object_library.h): called
  /// before the session is closed, so a complete session always has it. Required.
  std::function<void(const std::filesystem::path& file, const std::vector<BopObject>& objects, const std::string& source)>
      write_objects;
  void check() const;
};

/// The body name of the `instance`-th annotation of `obj_id` in a frame.
std::string BopBodyName(int obj_id, int instance);

/// Throws InputError for a bad scene (file, key or byte offset) or an `out` that is not empty.
ImportSummary ImportBop(const std::filesystem::path& scene_dir, const std::filesystem::path& models_dir,
                        const std::filesystem::path& out, const BopImportOptions& options = {});

}  // namespace mocap::import
