#pragma once
// The NDI way to an object mount: a tracked pointer whose tip is found by pivot calibration touches
// landmarks of the object whose mesh coordinates are known; paired-point registration of the touched
// points (in the object body's frame) to the mesh points gives T_objbody_mesh.
//
// Pivot calibration (NDI's "pivoting" procedure): the pointer is turned about its tip resting in a
// divot. For every sample i, T_tracker_pointer_i * p_pointer_tip = p_tracker_pivot; stacked as
// [R_i  -I] [p_pointer_tip; p_tracker_pivot] = -t_i and solved in the least-squares sense. The
// residual RMS is the tip's wobble; rotations about fewer than two independent axes leave the tip along
// the axis undetermined (reported, the smallest singular value).
// Paired points: Umeyama's closed form without scale (Eigen::umeyama), after at least 3 non-collinear
// pairs; the fiducial registration error (FRE) per landmark is reported.
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/rigid3.h"

namespace mocap {

struct PivotOptions {
  int min_samples = 20;          ///< pointer poses needed
  double min_rotation_deg = 20;  ///< largest angle between two samples below this: an error
  double max_rms_mm = 1.0;       ///< residual above this: a warning (the tip slipped in the divot)
  void check() const;            ///< throws InputError naming the field
};

struct PivotResult {
  Eigen::Vector3d p_pointer_tip = Eigen::Vector3d::Zero();     ///< tip in the pointer body's frame, m
  Eigen::Vector3d p_tracker_pivot = Eigen::Vector3d::Zero();   ///< the divot in the tracker frame, m
  double rms_mm = 0;          ///< RMS distance of the per-sample tip positions from the pivot
  double rotation_spread_deg = 0;
  double condition = 0;       ///< ratio of the largest to the smallest singular value of the system
  std::vector<std::string> warnings;
};

/// Throws InputError for too few samples or too little rotation (naming what to record instead).
PivotResult CalibratePivot(std::span<const Rigid3d> T_tracker_pointer, const PivotOptions& options = {});

struct PairedPointResult {
  Rigid3d T_objbody_mesh;
  double fre_rms_mm = 0;              ///< RMS residual of the pairs
  std::vector<double> fre_mm;         ///< per pair, in input order
};

/// T_objbody_mesh minimising sum |T * p_mesh_i - p_objbody_i|^2. Throws InputError for fewer than 3
/// pairs, spans of unequal size, or landmarks (nearly) on one line.
PairedPointResult RegisterPairedPoints(std::span<const Eigen::Vector3d> p_objbody, std::span<const Eigen::Vector3d> p_mesh);

}  // namespace mocap
