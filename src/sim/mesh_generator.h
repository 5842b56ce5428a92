#pragma once
// Procedural models of the objects of the automotive oil-change scene (SegICP paper, Fig. 1: an oil
// bottle, a funnel, an engine), the table they stand on, and a hand used as an occluder. Sizes are real
// ones, in metres; each mesh frame has its origin at the centre of the face the object rests on, z up,
// x towards the object's front (the bottle's spout, the engine's pulleys).
#include <string>
#include <vector>

#include "sim/mesh_builder.h"

namespace mocap::sim {

/// A 5-quart motor-oil jug: rounded-rectangle body 0.17 x 0.11 m, 0.28 m tall with its cap, spout at
/// the front, a grip handle at the back (yellow body, blue label band, black cap).
ColoredMesh GenerateOilBottle();
/// A blue plastic funnel: cone 0.152 m across, spout 0.055 m long, 0.15 m tall, 2 mm walls.
ColoredMesh GenerateFunnel();
/// An engine block on its oil pan: block, cylinder head, valve cover, exhaust and spark-plug bosses,
/// pulleys, oil filter, bell housing; about 0.46 x 0.32 x 0.31 m and 18k triangles.
ColoredMesh GenerateEngineBlock();
/// A table: 1.2 x 0.8 m top at 0.75 m, four legs; origin on the floor under the centre of the top.
ColoredMesh GenerateTable();
/// A hand (palm, fingers and thumb, 0.17 x 0.13 x 0.03 m), origin at the palm centre, fingers along +x.
ColoredMesh GenerateHand();

struct GeneratedMesh {
  std::string name;       ///< object name, also the file stem: "oil_bottle" -> oil_bottle.ply
  ColoredMesh mesh;
  Eigen::Vector3d declared_size_m;  ///< bounding-box size the model is meant to have
};

/// Every mesh above, in a fixed order.
std::vector<GeneratedMesh> GenerateAllMeshes();

/// Writes each mesh as `<out_dir>/<name>.ply`; returns the paths written. The library's objects.yaml
/// is written beside them by the pipeline (pipeline/record_stage.h), the one writer of that format.
/// Throws InputError when the folder cannot be written.
std::vector<std::string> WriteMeshLibrary(const std::string& out_dir);

}  // namespace mocap::sim
