#pragma once
// BOP scenes (thodan/bop_toolkit docs/bop_datasets_format.md):
//   SCENE/scene_camera.json  {"<im_id>": {"cam_K": [9, row-major], "depth_scale": mm per depth unit, ...}}
//   SCENE/scene_gt.json      {"<im_id>": [{"cam_R_m2c": [9, row-major], "cam_t_m2c": [3] mm, "obj_id": n}, ...]}
//   SCENE/rgb/<im_id:06d>.png|jpg, optional SCENE/depth/<im_id:06d>.png (uint16)
//   MODELS/models_info.json  {"<obj_id>": {"diameter": mm, ...}}, MODELS/obj_<obj_id:06d>.ply (mm)
// Poses are model-to-camera: p_camera = R p_model + t, i.e. T_camera_object; converted to metres here.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap::import {

struct BopObjectPose {
  int obj_id = 0;
  int instance = 0;        ///< 0 for the first instance of obj_id in the frame, 1 for the next, ...
  int gt_index = 0;        ///< index in scene_gt[im_id] (BOP's gt_id)
  Rigid3d T_camera_object;  ///< metres
};

struct BopFrame {
  int im_id = 0;
  PinholeCamera camera;          ///< cam_K; no distortion (BOP images are undistorted)
  double depth_scale_mm = 1.0;   ///< depth_mm = value * depth_scale (scene_camera)
  std::filesystem::path rgb;     ///< absolute path of the colour image
  std::filesystem::path depth;   ///< absolute path of the depth image, empty when absent
  std::vector<BopObjectPose> objects;
};

struct BopModel {
  int obj_id = 0;
  std::filesystem::path mesh;  ///< absolute path of obj_<id>.ply (mm)
  double diameter_m = 0.0;
  bool mesh_exists = false;
};

struct BopScene {
  std::filesystem::path dir;
  int scene_id = -1;                 ///< from the folder name when it is a number
  std::vector<BopFrame> frames;      ///< only frames whose colour image exists, by im_id
  int annotated_frames = 0;          ///< entries in scene_gt.json
  int frames_without_rgb = 0;        ///< annotated but no colour image present (not imported)
  std::vector<BopModel> models;      ///< from models_info.json, by obj_id
};

/// The BOP name of an object's mesh and body: "obj_000001".
std::string BopObjectName(int obj_id);

/// Reads a scene folder and the models folder. Image size comes from the first colour PNG's header
/// (or the dataset's camera.json two levels up). Throws InputError (file, key or byte offset) for
/// invalid JSON, a missing key, a K that is not a pinhole matrix, a non-rotation cam_R_m2c, an object
/// missing from models_info, or translations / diameters that look like metres instead of mm.
BopScene ReadBopScene(const std::filesystem::path& scene_dir, const std::filesystem::path& models_dir);

}  // namespace mocap::import
