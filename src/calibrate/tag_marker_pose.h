#pragma once
// The camera's pose in the tracker's world from one image of tags whose corners carry tracker markers
// (docs/calibration.md, "Camera pose from tags with markers on their corners").
//
// The setup of Pupil Labs' neon_mocap_localization (localize_neon_in_optitrack.py; data in
// ../shared/realdata/optitrack_neon_calib): AprilTags on a flat surface, one marker on each outer
// corner of each tag and one on its centre, tracked as one rigid body; a camera on a second tracked
// body takes one image of the tags. Upstream fits planes through the tag centres (camera) and the
// markers (tracker) and lines up their principal axes; we solve the perspective-n-point problem on the
// markers themselves (world points) and the detected corners (image points), which uses every corner
// and needs no tag size.
//
// What the markers cannot tell: a square grid of tags looks the same from the front and (mirrored)
// from behind, and a 2 x 2 grid also after a half turn in its plane. Those look-alike solutions fit
// the image equally well; the options' priors pick one and the result says how close the others came.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "calibrate/tag_detect.h"
#include "core/camera.h"
#include "core/rigid3.h"

namespace mocap {

/// Five markers of one tag: indices into the marker list; `corners` in cyclic order around the centre.
struct MarkedTag {
  size_t centre = 0;
  std::array<size_t, 4> corners{};
};

/// Finds the tags among tracker markers: a marker whose four nearest neighbours lie at one distance
/// (within `tolerance_m`) and average to its own position (within `tolerance_m`) is a tag centre, the
/// four are its corners, ordered by angle about the normal of the plane through all markers.
std::vector<MarkedTag> GroupTagMarkers(const std::vector<Eigen::Vector3d>& markers_world, double tolerance_m);

struct TagMarkerOptions {
  /// The world's up direction: a look-alike with the image's down axis pointing up is rejected.
  /// Motive's default is Y up; upstream's README requires Motive set up with Z up. Zero: no check.
  Eigen::Vector3d world_up = Eigen::Vector3d::UnitZ();
  /// A point near the camera (its tracked body's markers): the look-alike behind the tags is rejected.
  std::optional<Eigen::Vector3d> camera_near_world;
  double group_tolerance_m = 0.003;
  /// Solutions with RMS <= factor * best + 1 px are look-alikes: only the priors decide among them.
  double lookalike_factor = 2.0;
};

struct TagMarkerPose {
  Rigid3d T_world_camera;
  double rms_px = 0;                          ///< reprojection RMS of the corner markers
  std::vector<Eigen::Vector2d> residuals_px;  ///< per used corner: detected minus projected marker
  size_t tags_used = 0, corners_used = 0;
  std::vector<int> tag_id_of_group;  ///< detected tag id on each marked tag (GroupTagMarkers order)
  /// Centre markers (not used in the fit) projected vs the tag's centre in the image (the crossing of
  /// its diagonals, a projective invariant): an independent check of the fit, pixels.
  double centre_rms_px = 0;
  size_t lookalikes = 0;           ///< other solutions within the look-alike band
  double rejected_best_rms_px = 0;  ///< the best of those (priors rejected it), pixels
  double rejected_camera_shift_m = 0;  ///< how far its camera is from the chosen one
  std::vector<std::string> warnings;
};

/// Tries every assignment of detected tags to marked tags, each with the 4 cyclic shifts and both
/// orientations of the corner order (one shared by all tags: the tags are printed the same way up),
/// solving cv::solvePnP (SQPnP) then cv::solvePnPRefineLM with the camera's full distortion model.
/// Throws InputError when no marked tag is found, more tags are detected than marked (or more than
/// 6 are marked: 6! assignments), or no solution satisfies the priors.
TagMarkerPose LocateCameraByTagMarkers(const std::vector<TagDetection>& tags,
                                       const std::vector<Eigen::Vector3d>& markers_world,
                                       const PinholeCamera& camera, const TagMarkerOptions& options = {});

/// The form upstream saves (neon_camera_pose_relative_to_markers.json): the camera's rotation in
/// world axes, R_world_camera, and its position minus the mean of its body's markers, in world axes
/// (not the body's axes: it is only valid while the body keeps the orientation it had in the take).
struct MarkerCentroidRelativePose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d R_world_camera = Eigen::Matrix3d::Identity();
};
MarkerCentroidRelativePose RelativeToMarkerCentroid(const Rigid3d& T_world_camera,
                                                    const std::vector<Eigen::Vector3d>& body_markers_world);

}  // namespace mocap
