#pragma once
// The calibration self-check: from a validated session, which calibration item looks wrong and by how
// much (docs/calibration.md "Checking a calibration").
//
// Each validated record pairs a label L = T_camera_mesh_label with SegICP's estimate E from the measured
// depth. If the depth is right, E is the truth, and each wrong item leaves its own trace in E vs L:
//   a camera mount off by D_c (E = D_c L, the same D_c for every object that camera sees):
//     the corrected mount is T_cambody_camera * inv(D_c);
//   an object mount off by O_k (E = L O_k, the same O_k in every frame of object k):
//     the corrected mount is T_objbody_mesh * O_k;
//   a tracker latency off by e (labels taken from the tracker e too late: E = L moved back by e along
//     its own motion, v and w from neighbouring labels): the corrected latency is tracker_latency_ns - e.
// All three are fitted jointly as one model E_i = D_c * Shift(L_i, -e) * O_k by Ceres (Huber loss, each
// object's residuals scaled by their own robust spread), but only the items a greedy forward selection
// lets in: at each step the candidate that lowers the cost most is tried, and it stays when its
// estimate is both larger than the smallest error worth reporting and significant (size > z * its
// standard error). The standard errors come from Ceres' covariance, scaled by the fit's residual
// variance and widened by the residuals' lag-1 autocorrelation (neighbouring frames are not
// independent). Items that explain the residuals almost equally well (a static camera looking at one
// static object cannot tell a camera mount from an object mount) are named together in a warning.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/rigid3.h"

namespace mocap {

/// One validated record with a reliable SegICP estimate.
struct CheckRecord {
  std::string camera;
  std::string object;
  int instance = 0;
  int64_t stamp_ns = 0;
  Rigid3d T_camera_mesh_label;
  Rigid3d T_camera_mesh_segicp;
  /// The axis of a body of revolution (mesh frame; zero for none): the validator reports its estimate
  /// with the label's spin (validate/label_check.h ApplySymmetry), so the rotation about this axis is
  /// not a measurement and is left out of the residual.
  Eigen::Vector3d spin_axis_mesh = Eigen::Vector3d::Zero();
  /// The directions of the estimate the depth judged (the validator's analysis, validate/observability.h),
  /// when it judged fewer than six: orthonormal columns in analysis coordinates [L w; v] (mesh frame,
  /// about center_mesh, rotation scaled by L = radius_m). Along the others the estimate is where the label
  /// or the outline put it, not a measurement (a table top's slide in its plane), so the residual is
  /// taken in these alone. None: all six.
  struct Judged {
    Eigen::Matrix<double, 6, Eigen::Dynamic> directions;
    Eigen::Vector3d center_mesh = Eigen::Vector3d::Zero();
    double radius_m = 1.0;
  };
  std::optional<Judged> judged = std::nullopt;
};

struct CalibrationCheckOptions {
  /// Mount errors smaller than both bounds are not reported. An object's rotation gets a wider bound:
  /// SegICP's rotation of a shiny or nearly symmetric object is biased by up to about 1.5 degrees with
  /// the true calibration (docs/calibration.md), while a camera's rotation moves every object it sees.
  double min_mount_mm = 2.0;
  double min_camera_mount_deg = 0.5;
  double min_object_mount_deg = 3.0;
  /// Objects whose estimates scatter more than this (robust standard deviation of the residual, per
  /// axis) are left out with a warning: the depth does not pin their pose (a plane, a hidden object).
  double max_spread_mm = 10.0;
  double max_spread_deg = 5.0;
  double min_latency_ms = 5.0;     ///< latency errors below this are not reported
  double significance = 4.0;       ///< z: an item is reported only when its size exceeds z standard errors
  int min_records = 20;            ///< records needed in all
  int max_items = 5;               ///< most items (a mount's rotation and translation count apart) let in
  int64_t max_neighbour_gap_ns = 250'000'000;  ///< labels further apart do not give a velocity
  double huber_sigmas = 3.0;       ///< Huber loss scale, in robust standard deviations
  double min_sigma_mm = 0.3;       ///< floors of the per-object residual scales
  double min_sigma_deg = 0.1;
  double similar_share = 0.9;      ///< a runner-up explaining this share of the winner's gain is named
  void check() const;              ///< throws InputError naming the field
};

enum class CheckItemKind { kCameraMount, kObjectMount, kLatency };
std::string_view ToString(CheckItemKind kind);
struct CheckFinding;
/// A mount finding's size as reports write it: "4.40 mm (95 %: +-0.26)", "3.10 deg (95 %: +-0.20)" or
/// both, the parts the check let in (a zero interval: not fitted).
std::string MountSizeText(const CheckFinding& finding);

/// A calibration item that looks wrong.
struct CheckFinding {
  CheckItemKind kind = CheckItemKind::kCameraMount;
  std::string name;                  ///< the camera or the object; empty for the latency
  Rigid3d correction;                ///< D_c (camera) or O_k (object), see above; identity for the latency
  double size_mm = 0, size_deg = 0;  ///< of the correction
  double ci95_mm = 0, ci95_deg = 0;  ///< half-widths of 95 % intervals of the sizes
  double latency_error_ms = 0;       ///< e (positive: the rig's latency is too large by e)
  double latency_ci95_ms = 0;
  double explained_share = 0;        ///< share of the robust cost without any item that this item removes
  std::vector<std::string> alike;    ///< other items that explain the residuals almost as well
};

/// Residuals of one object (or camera) before and after the findings are applied.
struct ResidualSummary {
  std::string camera, object;
  int records = 0;
  double median_mm_before = 0, median_deg_before = 0;
  double median_mm_after = 0, median_deg_after = 0;
};

struct CalibrationCheckResult {
  std::vector<CheckFinding> findings;  ///< empty: nothing looks wrong
  std::vector<ResidualSummary> residuals;
  int records = 0;               ///< used
  std::vector<std::string> objects_left_out;  ///< their estimates scatter too much (see max_spread_mm)
  int records_with_motion = 0;  ///< with neighbours close enough for a velocity
  double autocorrelation = 0;   ///< lag-1, of the final residuals
  std::vector<std::string> warnings;
};

/// Throws InputError for invalid options and for fewer than min_records records.
CalibrationCheckResult CheckCalibration(std::span<const CheckRecord> records, const CalibrationCheckOptions& options = {});

}  // namespace mocap
