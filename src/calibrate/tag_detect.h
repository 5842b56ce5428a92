#pragma once
// AprilTag (or ArUco) squares found in a distorted camera image, with corners refined against the
// camera's lens model. Used where a tag board's corners carry tracker markers (docs/calibration.md,
// "Camera pose from tags with markers on their corners").
//
// Why our own corner refinement: OpenCV 4.6's aruco fits its corner lines in the raw image, where a
// wide-angle lens bends the tag's edges (the Pupil Labs Neon scene camera: k1 = -0.13 with a rational
// model), and its sub-pixel corner search is pulled by the tracker markers glued onto the corners.
// Like the AprilTag library's `refine_edges` (upstream neon_mocap_localization runs pupil_apriltags on
// an undistorted copy of the image), we fit each edge as a straight line, but in undistorted
// normalised coordinates and only on the middle 60 % of each edge, away from the markers.
#include <opencv2/core.hpp>

#include <Eigen/Core>
#include <array>
#include <string_view>
#include <vector>

#include "core/camera.h"

namespace mocap {

struct TagDetection {
  int id = -1;
  /// Outer corners of the tag's black border, pixels (OpenCV centres), in OpenCV's order: clockwise in
  /// the image starting at the tag's own top-left corner.
  std::array<Eigen::Vector2d, 4> corners_px;
  /// RMS distance of the sampled edge points to their fitted lines, pixels; 0 when not refined.
  double edge_rms_px = 0;
  bool refined = false;  ///< false: an edge had too few clear edge points; OpenCV's corners are kept
};

/// Detects the tags of `dictionary` (an OpenCV name such as "DICT_APRILTAG_36h11") in an 8-bit grey or
/// BGR image and refines their corners with `RefineTagCorners`. Throws InputError for an empty image,
/// another pixel type, a camera of another size, or an unknown dictionary. Finding none is not an error.
std::vector<TagDetection> DetectTags(const cv::Mat& image, std::string_view dictionary,
                                     const PinholeCamera& camera);

/// Moves each corner to the intersection of its two edges, each edge a least-squares line through
/// points where the grey level rises most steeply from the dark border outwards, sampled at 40 places
/// on the middle 60 % of the edge and fitted in undistorted normalised coordinates (outliers beyond 3
/// times the median distance dropped once). Three passes; the first searches +-8 px across the edge,
/// the others +-3 px. Precondition: `gray` is CV_8UC1 of the camera's size.
void RefineTagCorners(const cv::Mat& gray, const PinholeCamera& camera, TagDetection& tag);

}  // namespace mocap
