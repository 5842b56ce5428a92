#pragma once
// The model behind CheckCalibration (calibration_check.h): per record, the prediction
//   E_pred = D_c * Shift(L, -e) * O_k,   Shift(L, -e) = (exp(-e w) R_L, p_L - e v)
// and its residual [log(R_E R_pred^T) / sigma_rad; (p_E - p_pred) / sigma_m], fitted by Ceres over the
// items set free (the others stay at identity / zero).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <span>
#include <string>
#include <vector>

#include "calibrate/calibration_check.h"

namespace mocap::check_model {

struct ModelRecord {
  int camera = 0, object = 0;  ///< indices into the check's camera and object lists
  Eigen::Quaterniond q_label = Eigen::Quaterniond::Identity(), q_segicp = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_label_m = Eigen::Vector3d::Zero(), p_segicp_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_m_per_s = Eigen::Vector3d::Zero();    ///< label's velocity, camera frame
  Eigen::Vector3d w_rad_per_s = Eigen::Vector3d::Zero();  ///< label's angular velocity, camera frame
  bool has_motion = false;
  Eigen::Vector3d spin_axis_camera = Eigen::Vector3d::Zero();  ///< unit, or zero: see CheckRecord
  /// The residual's part in the directions the depth judged (CheckRecord::judged): a projection of the
  /// unscaled residual [rotation rad; position m] (camera frame); the identity when all six were.
  Eigen::Matrix<double, 6, 6> judged_part = Eigen::Matrix<double, 6, 6>::Identity();
  double sigma_m = 1e-3, sigma_rad = 1e-3;  ///< the object's robust residual scales
};

/// One unknown of the model: the rotation or the translation of a mount (each enters on its own: a
/// pure shift of the camera is not also explained by a small turn that does the same at the objects'
/// depth), or the latency.
enum class Part { kRotation, kTranslation };
struct Item {
  CheckItemKind kind = CheckItemKind::kCameraMount;
  int index = 0;                  ///< camera or object index; 0 for the latency
  Part part = Part::kTranslation;  ///< mounts only
  bool operator==(const Item& other) const {
    return kind == other.kind && index == other.index && (kind == CheckItemKind::kLatency || part == other.part);
  }
};

/// The check's records as the model sees them: cameras and objects by name (the records' indices point
/// here), and the records of each (camera, instance) track in stamp order.
struct Prepared {
  std::vector<ModelRecord> records;
  std::vector<std::string> cameras, objects;
  std::vector<std::vector<int>> tracks;
};

/// Indices, velocities from neighbouring labels of a track (central differences where both neighbours
/// are within max_neighbour_gap_ns, one-sided where one is), and each object's residual scales with no
/// item applied (1.4826 MAD about the median per component, floored).
Prepared Prepare(std::span<const CheckRecord> records, const CalibrationCheckOptions& options);

/// Angle-axis (3) then translation (3) per camera and object; the latency error in seconds.
struct Params {
  std::vector<std::array<double, 6>> camera, object;
  double latency_s = 0;
};

struct Fit {
  Params params;
  double cost = 0;  ///< Ceres' robust cost at the solution
  /// Per free item, the covariance of its parameters (3x3 for a mount's part, 1x1 for the latency), scaled by
  /// the residual variance factor; empty when Ceres could not compute it.
  std::vector<Eigen::MatrixXd> covariance;
};

/// The unscaled residual [rotation rad; position m] of one record under `params`.
Eigen::Matrix<double, 6, 1> Residual(const ModelRecord& record, const Params& params);

/// Fits the free items; the others held at zero. `huber` is the loss scale in scaled residual units.
Fit FitItems(const std::vector<ModelRecord>& records, int cameras, int objects, const std::vector<Item>& free,
             double huber);

/// Ceres' robust cost (0.5 sum of Huber(|scaled residual|^2)) of the records under `params`.
double RobustCost(const std::vector<ModelRecord>& records, const Params& params, double huber);

/// The robust cost with every item at zero.
double CostWithoutItems(const std::vector<ModelRecord>& records, int cameras, int objects, double huber);

/// Lag-1 autocorrelation of the scaled residuals along the tracks, clamped to [0, 0.95].
double ResidualAutocorrelation(const Prepared& prepared, const Params& params);

}  // namespace mocap::check_model
