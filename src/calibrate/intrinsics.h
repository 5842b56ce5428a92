#pragma once
// Camera intrinsics from views of a calibration board (cv::calibrateCamera), with the diagnostics a
// user needs to judge the result: per-view RMS, image coverage, the views rejected and why.
#include <opencv2/core.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "calibrate/board.h"
#include "core/camera.h"

namespace mocap {

/// Distortion coefficients estimated (the others are held at 0).
enum class DistortionModel : uint8_t {
  kK1K2P1P2 = 0,    ///< k3 fixed at 0 (cv::CALIB_FIX_K3): narrow lenses, few views
  kK1K2P1P2K3 = 1,  ///< OpenCV's default five coefficients
  kRational = 2,    ///< k1..k6 (cv::CALIB_RATIONAL_MODEL): wide lenses, many views
};

struct IntrinsicsOptions {
  int min_views = 10;              ///< usable views needed
  int min_corners_per_view = 8;    ///< a view with fewer detected corners is rejected
  DistortionModel model = DistortionModel::kK1K2P1P2K3;
  double max_view_rms_px = 1.0;    ///< views above this RMS after a first fit are rejected, then refit once
  int coverage_cells_x = 8;        ///< the image grid of the coverage measure
  int coverage_cells_y = 6;
  double min_coverage = 0.6;       ///< below this fraction of cells holding a corner: a warning
  double max_focal_std_fraction = 0.002;  ///< fx/fy standard deviation above this fraction: a warning
  /// Throws InputError naming the field.
  void check() const;
};

struct RejectedView {
  int index = 0;       ///< into the input views
  std::string reason;  ///< one line: what was wrong with it
};

struct IntrinsicsResult {
  PinholeCamera camera;
  double rms_px = 0;                ///< over all corners of the views used
  std::vector<int> views_used;      ///< indices into the input views
  std::vector<double> view_rms_px;  ///< parallel to views_used
  std::vector<RejectedView> views_rejected;
  double coverage = 0;              ///< fraction of the coverage grid's cells holding a used corner
  /// Standard deviations (pixels) of fx, fy, cx, cy from cv::calibrateCamera's covariance.
  double fx_std_px = 0, fy_std_px = 0, cx_std_px = 0, cy_std_px = 0;
  std::vector<std::string> warnings;  ///< each says what to record to fix it
};

/// Calibrates from one detection per image (DetectBoard). Views not found, with too few corners or
/// with collinear corners are rejected before the fit; views whose RMS exceeds max_view_rms_px after
/// the first fit are rejected and the fit repeated once.
/// Throws InputError when options, spec or image size are invalid, and "too few usable views: N of M
/// (need K); ..." (with the reasons) when fewer than options.min_views remain.
IntrinsicsResult CalibrateIntrinsics(std::span<const BoardDetection> views, cv::Size image_size,
                                     const BoardSpec& spec, const IntrinsicsOptions& options = {});

/// Fraction of a cells_x by cells_y grid over the image that holds at least one of the corners.
double ImageCoverage(std::span<const BoardDetection> views, std::span<const int> indices, cv::Size image_size,
                     int cells_x, int cells_y);

}  // namespace mocap
