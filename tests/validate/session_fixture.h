#pragma once
// Helpers for session-level validation tests: sessions with measured depth built from real BOP data,
// labels perturbed on purpose, and the rates the issue asks for. They take any session + label folder,
// so a simulated Kinect session (`mocaplabel sim record`, then `mocaplabel label`) plugs in the same way.
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/rigid3.h"
#include "validate/session_check.h"

namespace mocap::testing {

/// A fresh, empty folder under the system temp directory.
std::filesystem::path FreshTempDir(const std::string& name);

/// The objects of a session's objects.yaml (what `mocaplabel validate` reads by default).
std::vector<ValidationObject> SessionObjects(const std::filesystem::path& session_dir);

/// LM-O scene 2 (../shared/realdata/bop_lmo_scene2) has ground-truth poses and real meshes but no depth
/// images. This builds, under `dir`:
///   L   the label run of the imported scene (instance PNGs, rendered depth, overlays),
///   S   a session of the same frames whose depth is the label run's rendered depth of all objects with
///       Kinect1 axial noise (sigma 1.425e-3 z^2 m) and 1 mm quantisation (the BOP depth_scale).
/// Frames listed in `frames_without_depth` (stream indices) get no depth image.
struct BopDepthScene {
  std::filesystem::path session, labels;
  std::vector<ValidationObject> objects;
};
BopDepthScene MakeBopDepthScene(const std::filesystem::path& dir, const std::vector<int64_t>& frames_without_depth,
                                uint32_t seed);

/// Copies a label run's labels.jsonl into `out_labels` with every pose replaced by
/// perturb(T_camera_object), and links the label images (the masks stay those of the correct labels).
using Perturbation = std::function<Rigid3d(const Rigid3d& T_camera_object)>;
void WritePerturbedLabels(const std::filesystem::path& labels, const std::filesystem::path& out_labels,
                          const Perturbation& perturb);

/// Copies a label run's labels.jsonl into `out_labels` without the records of object `object_id`, and
/// links the label images.
void WriteLabelsWithoutObject(const std::filesystem::path& labels, const std::filesystem::path& out_labels,
                              int object_id);

/// A mount error: T_camera_object * T_object_mount with a fixed translation (metres) and rotation (deg)
/// about random directions.
Perturbation MountError(double translation_m, double angle_deg, uint32_t seed);

/// Fractions over the records whose input was usable (an estimate was attempted).
struct Rates {
  int64_t checked = 0;
  double accepted = 0.0;  ///< verdict accept
  double flagged = 0.0;   ///< verdict suspect or reject
  double success = 0.0;   ///< the paper's criterion
};
Rates ComputeRates(const SessionValidation& validation);

}  // namespace mocap::testing
