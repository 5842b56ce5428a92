#include "calibrate/intrinsics.h"

#include <opencv2/calib3d.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "calibrate/cv_convert.h"
#include "core/check.h"

namespace mocap {
namespace {

struct Fit {
  cv::Mat K, dist, std_intrinsics;
  std::vector<double> view_rms_px;
  double rms_px = 0;
};

int CalibrationFlags(DistortionModel model) {
  switch (model) {
    case DistortionModel::kK1K2P1P2: return cv::CALIB_FIX_K3;
    case DistortionModel::kK1K2P1P2K3: return 0;
    case DistortionModel::kRational: return cv::CALIB_RATIONAL_MODEL;
  }
  return 0;
}

/// True when the detected corners lie on (nearly) one line of the board: no homography, no view.
bool CornersCollinear(const BoardDetection& view, const std::vector<Eigen::Vector3d>& points_board, double square_m) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (int id : view.corner_ids) mean += points_board[static_cast<size_t>(id)].head<2>();
  mean /= static_cast<double>(view.corner_ids.size());
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  for (int id : view.corner_ids) {
    const Eigen::Vector2d d = points_board[static_cast<size_t>(id)].head<2>() - mean;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(view.corner_ids.size());
  const double minor = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance).eigenvalues()(0);
  return std::sqrt(std::max(minor, 0.0)) < 0.1 * square_m;
}

/// Empty when the view can enter the fit, else why not.
std::string PreFitRejection(const BoardDetection& view, const BoardSpec& spec, const IntrinsicsOptions& options,
                            const std::vector<Eigen::Vector3d>& points_board) {
  if (!view.found()) return "board not found: " + view.failure;
  const int corners = static_cast<int>(view.corner_ids.size());
  if (corners < options.min_corners_per_view)
    return Str(corners, " corners detected (need ", options.min_corners_per_view, ")");
  if (CornersCollinear(view, points_board, spec.square_m)) return "the detected corners lie on one line";
  return "";
}

void RequireViews(size_t usable, size_t total, const IntrinsicsOptions& options,
                  const std::vector<RejectedView>& rejected) {
  if (static_cast<int>(usable) >= options.min_views) return;
  std::string why;
  for (size_t i = 0; i < rejected.size() && i < 5; ++i) why += Str("; view ", rejected[i].index, ": ", rejected[i].reason);
  if (rejected.size() > 5) why += Str("; and ", rejected.size() - 5, " more");
  throw InputError("intrinsics", Str("too few usable views: ", usable, " of ", total, " (need ", options.min_views,
                                     "); record the board in more positions: the whole image including its corners "
                                     "and edges, tilted 20-45 degrees, at several distances", why));
}

Fit RunCalibrateCamera(std::span<const BoardDetection> views, const std::vector<int>& used,
                       const std::vector<Eigen::Vector3d>& points_board, cv::Size image_size, int flags) {
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (int i : used) {
    object.push_back(CvObjectPoints(views[static_cast<size_t>(i)], points_board));
    image.push_back(CvImagePoints(views[static_cast<size_t>(i)]));
  }
  Fit fit;
  std::vector<cv::Mat> rvecs, tvecs;
  cv::Mat std_extrinsics, per_view;
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12);
  fit.rms_px = cv::calibrateCamera(object, image, image_size, fit.K, fit.dist, rvecs, tvecs, fit.std_intrinsics,
                                   std_extrinsics, per_view, flags, stop);
  per_view.reshape(1, 1).copyTo(fit.view_rms_px);
  return fit;
}

/// Moves the views above max_view_rms_px from views_used to views_rejected; true when any moved.
bool RejectHighRmsViews(const Fit& fit, const IntrinsicsOptions& options, IntrinsicsResult& result) {
  std::vector<int> kept;
  for (size_t k = 0; k < result.views_used.size(); ++k) {
    if (fit.view_rms_px[k] <= options.max_view_rms_px) kept.push_back(result.views_used[k]);
    else result.views_rejected.push_back({result.views_used[k], Str("reprojection RMS ", fit.view_rms_px[k], " px > ",
        options.max_view_rms_px, " px in the first fit: motion blur, a mis-detected corner or a bent board")});
  }
  const bool rejected = kept.size() != result.views_used.size();
  result.views_used = std::move(kept);
  return rejected;
}

void FillResult(const Fit& fit, cv::Size image_size, IntrinsicsResult& result) {
  result.camera = CameraFromCv(fit.K, fit.dist, image_size);
  result.rms_px = fit.rms_px;
  result.view_rms_px = fit.view_rms_px;
  result.fx_std_px = fit.std_intrinsics.at<double>(0);
  result.fy_std_px = fit.std_intrinsics.at<double>(1);
  result.cx_std_px = fit.std_intrinsics.at<double>(2);
  result.cy_std_px = fit.std_intrinsics.at<double>(3);
}

void AddWarnings(const IntrinsicsOptions& options, IntrinsicsResult& result) {
  if (result.coverage < options.min_coverage)
    result.warnings.push_back(Str("the corners cover only ", std::lround(100 * result.coverage), " % of the image (",
                                  options.coverage_cells_x, "x", options.coverage_cells_y,
                                  " cells); add views with the board near the image corners and edges, where "
                                  "the distortion shows"));
  const double worst = std::max(result.fx_std_px / result.camera.fx, result.fy_std_px / result.camera.fy);
  if (worst > options.max_focal_std_fraction)
    result.warnings.push_back(Str("the focal length is uncertain (fx +- ", result.fx_std_px, " px, fy +- ",
                                  result.fy_std_px, " px); add views with the board tilted 30-45 degrees "
                                  "towards the camera, from several sides"));
}

}  // namespace

void IntrinsicsOptions::check() const {
  if (min_views < 3) throw InputError("IntrinsicsOptions.min_views", Str("is ", min_views, "; need >= 3"));
  if (min_corners_per_view < 4)
    throw InputError("IntrinsicsOptions.min_corners_per_view", Str("is ", min_corners_per_view, "; need >= 4"));
  if (!(max_view_rms_px > 0)) throw InputError("IntrinsicsOptions.max_view_rms_px", "must be positive");
  if (coverage_cells_x < 1 || coverage_cells_y < 1)
    throw InputError("IntrinsicsOptions.coverage_cells_x/y", "must be at least 1");
  if (!(min_coverage >= 0 && min_coverage <= 1)) throw InputError("IntrinsicsOptions.min_coverage", "must lie in [0, 1]");
  if (!(max_focal_std_fraction > 0)) throw InputError("IntrinsicsOptions.max_focal_std_fraction", "must be positive");
}

double ImageCoverage(std::span<const BoardDetection> views, std::span<const int> indices, cv::Size image_size,
                     int cells_x, int cells_y) {
  std::vector<char> hit(static_cast<size_t>(cells_x * cells_y), 0);
  for (int i : indices)
    for (const Eigen::Vector2d& p : views[static_cast<size_t>(i)].corners_px) {
      const int cx = std::clamp(static_cast<int>((p.x() + 0.5) / image_size.width * cells_x), 0, cells_x - 1);
      const int cy = std::clamp(static_cast<int>((p.y() + 0.5) / image_size.height * cells_y), 0, cells_y - 1);
      hit[static_cast<size_t>(cy * cells_x + cx)] = 1;
    }
  return static_cast<double>(std::count(hit.begin(), hit.end(), 1)) / static_cast<double>(hit.size());
}

IntrinsicsResult CalibrateIntrinsics(std::span<const BoardDetection> views, cv::Size image_size,
                                     const BoardSpec& spec, const IntrinsicsOptions& options) {
  options.check();
  spec.check();
  if (image_size.width <= 0 || image_size.height <= 0)
    throw InputError("intrinsics", Str("image size ", image_size.width, "x", image_size.height, " is not positive"));
  const std::vector<Eigen::Vector3d> points_board = BoardCornerPoints(spec);
  IntrinsicsResult result;
  for (size_t i = 0; i < views.size(); ++i) {
    std::string reason = PreFitRejection(views[i], spec, options, points_board);
    if (reason.empty()) result.views_used.push_back(static_cast<int>(i));
    else result.views_rejected.push_back({static_cast<int>(i), std::move(reason)});
  }
  RequireViews(result.views_used.size(), views.size(), options, result.views_rejected);
  const int flags = CalibrationFlags(options.model);
  Fit fit = RunCalibrateCamera(views, result.views_used, points_board, image_size, flags);
  if (RejectHighRmsViews(fit, options, result)) {
    RequireViews(result.views_used.size(), views.size(), options, result.views_rejected);
    fit = RunCalibrateCamera(views, result.views_used, points_board, image_size, flags);
  }
  FillResult(fit, image_size, result);
  result.coverage = ImageCoverage(views, result.views_used, image_size, options.coverage_cells_x, options.coverage_cells_y);
  AddWarnings(options, result);
  return result;
}

}  // namespace mocap
