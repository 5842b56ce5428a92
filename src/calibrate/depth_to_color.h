#pragma once
// The extrinsic between an RGB-D sensor's depth camera and its colour camera (a Kinect v2's ToF camera
// sits about 5 cm beside its colour camera) from the calibration board, without an infrared image: in
// every view the board is a plane, seen by the colour camera as a pose (the detected corners) and by the
// depth camera as points. With n.p = d the plane (unit normal towards the camera, d > 0),
// p_color = R p_depth + t gives n_c = R n_d and d_c = d_d + n_c . t: the rotation from the normals
// (Kabsch), the translation from the offsets (least squares), as in the plane-based camera-to-range-
// sensor calibration of Zhang and Pless (2004). Planes turned about at least two axes are needed: with
// normals all alike the translation across them is not determined.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/rigid3.h"

namespace mocap {

/// n . p = d, |n| = 1, d >= 0 (the normal faces the camera at the origin).
struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset_m = 0;
};

/// The board's plane in the colour camera from its pose (T_color_board: the board is z = 0).
Plane BoardPlane(const Rigid3d& T_color_board);

struct PlaneFitOptions {
  double inlier_m = 0.01;  ///< RANSAC: points this close to a candidate plane agree
  int iterations = 200;
  int min_points = 200;    ///< fewer inliers: no plane
  void check() const;      ///< throws InputError naming the field
};

struct PlaneFit {
  Plane plane;
  int inliers = 0;
  double rms_mm = 0;  ///< of the inliers' distances to the least-squares plane
};

/// RANSAC over point triples (a fixed seed), then least squares (smallest principal axis) on the inliers.
std::optional<PlaneFit> FitPlane(std::span<const Eigen::Vector3d> points, const PlaneFitOptions& options = {});

struct PlanePair {
  Plane depth;  ///< fitted to the depth camera's points of the board
  Plane color;  ///< from the board's pose in the colour image
};

struct DepthToColorOptions {
  int min_views = 6;
  /// The normals' spread (the smaller principal angle of their scatter about the mean) below this:
  /// the translation across the normals is poorly determined, a warning.
  double min_normal_spread_deg = 10;
  void check() const;
};

struct DepthToColorResult {
  Rigid3d T_color_depth;
  std::vector<double> offset_error_mm;  ///< per view: d_c - (d_d + n_c . t)
  std::vector<double> normal_error_deg; ///< per view: angle(n_c, R n_d)
  double offset_rms_mm = 0, normal_rms_deg = 0;
  double normal_spread_deg = 0;
  std::vector<std::string> warnings;
};

/// Throws InputError for fewer than min_views pairs or normals (nearly) all alike (then nothing but the
/// offset along them is determined).
DepthToColorResult EstimateDepthToColor(std::span<const PlanePair> views, const DepthToColorOptions& options = {});

}  // namespace mocap
