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
// Touches: in a recording the pointer rests on each landmark in turn; the rests are the stretches in
// which the tip, expressed in the object body's frame, stays within a small ball for long enough
// (the object may move meanwhile: in its own frame the tip still rests).
#include <cstdint>
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
  /// A pose whose tip lands further than this from the pivot is not pivoting (the pointer being put into
  /// or taken out of the divot): dropped (RANSAC over triples of poses, then least squares on the rest).
  double outlier_mm = 2.0;
  void check() const;            ///< throws InputError naming the field
};

struct PivotResult {
  Eigen::Vector3d p_pointer_tip = Eigen::Vector3d::Zero();     ///< tip in the pointer body's frame, m
  Eigen::Vector3d p_tracker_pivot = Eigen::Vector3d::Zero();   ///< the divot in the tracker frame, m
  double rms_mm = 0;          ///< RMS distance of the per-sample tip positions from the pivot
  double rotation_spread_deg = 0;
  double condition = 0;       ///< ratio of the largest to the smallest singular value of the system
  int samples_used = 0, samples_dropped = 0;
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

struct TouchOptions {
  double min_still_s = 0.5;    ///< a rest shorter than this is passing by, not a touch
  /// The tip stays this close to the rest's running mean (single samples beyond are skipped; three
  /// in a row end the rest).
  double still_radius_mm = 2.0;
  double max_gap_s = 0.1;      ///< samples further apart than this (tracking lost) end a rest
  /// Touches whose distances differ from the landmarks' by more than this (RMS) are not those landmarks.
  double max_mismatch_mm = 5.0;
  void check() const;          ///< throws InputError naming the field
};

struct Touch {
  int64_t start_ns = 0, end_ns = 0;
  Eigen::Vector3d p_objbody = Eigen::Vector3d::Zero();  ///< component-wise median of the rest's tip positions
  double spread_mm = 0;  ///< RMS distance of the rest's samples from that median
  int samples = 0;
};

/// The rests of the tip, in time order. `stamps_ns` increasing, parallel to `p_objbody_tip`.
std::vector<Touch> FindTouches(std::span<const int64_t> stamps_ns, std::span<const Eigen::Vector3d> p_objbody_tip,
                               const TouchOptions& options = {});

struct TouchMatch {
  std::vector<int> touches;   ///< per landmark, the index of the touch matched to it (increasing)
  double distance_rms_mm = 0; ///< RMS difference of the pairwise distances, touches vs landmarks
};

/// Which rests were the landmarks: the pointer also rests where it lies between uses. Distances are
/// what a rigid object keeps, so among the ordered choices of one rest per landmark (the landmarks
/// touched in the file's order) the one whose pairwise tip distances best match the landmarks' wins.
/// InputError when there are fewer rests than landmarks, or more than 24 (record only the touching).
TouchMatch MatchTouchesToLandmarks(std::span<const Touch> touches, std::span<const Eigen::Vector3d> p_mesh);

}  // namespace mocap
