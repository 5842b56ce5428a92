#pragma once
// Which directions of an object's pose the measured depth constrains. A depth point constrains the pose
// along its surface normal: moving the model within its own surface (a table top sliding in its plane, a
// funnel spinning about its axis of revolution) leaves every point on the scene surface. The first-order
// change of the point-to-plane residual of model point p (normal n, object frame) under a small motion
// [w, v] is (p x n).w + n.v, so the information of the registration is A = sum_i J_i J_i^T with
// J_i = [(p_i - c) x n_i / L ; n_i] over the model points the scene supports (a scene point within tau),
// c their centroid and L their RMS radius (both halves in metres). Eigenvectors of A with little
// information may still be seen through the object's outline: a box showing two faces slides along their
// common edge only by moving the faces' ends. So each weak direction is probed: the pose is moved 1 cm
// (RMS over the crop) along it, the crop seen from there taken again (clipped by the image and by what
// hides it, as the frame sees it), and when that costs the alignment a share of its supported points the
// direction is observable. The others are reported unobservable, and the verdict judges the estimate's
// difference from the label only in the observable ones (docs/validation.md "Degrees of freedom").
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "core/rigid3.h"
#include "validate/model_crop.h"
#include "validate/point_grid.h"

namespace mocap {

/// Weak directions with less information than this have no normal against them (a table top's slide can
/// lose a few percent of its edge points to the probe and yet no surface resists it): the point-to-plane
/// polish does not move along them; the outline estimate (validate/outline.h) judges their slides.
inline constexpr double kMinProbedInformation = 0.01;

/// The robust kernel's scale never drops below the depth's quantisation at a metre (about 1 mm).
inline constexpr double kMinRobustScaleM = 0.001;

/// Geman-McClure weights of point-to-plane residuals (observability.cc says why).
std::vector<double> RobustWeights(const std::vector<double>& r, double sigmas, double min_scale_m);

struct ObservabilityOptions {
  /// Information per supporting point from which a direction counts as observable by the surface normals
  /// alone. A direction every point's normal lies along scores 1.
  double min_information = 0.1;
  /// Directions below min_information are probed: observable when moving the pose `probe_m` along them
  /// (RMS displacement over the crop) loses at least `probe_min_loss` of the crop points with a scene
  /// point within `probe_support_m` (tighter than tau, which a point moved 1 cm along a slope still meets;
  /// a few times the sensor's noise).
  double probe_m = 0.01;
  double probe_support_m = 0.004;
  double probe_min_loss = 0.03;
  /// ... and at least this many crop points: a share of a few dozen points is a handful of points near
  /// the support gate, which the depth's noise alone moves across it.
  int probe_min_lost_points = 10;
  /// A model point is supported when a scene point lies within this (the alignment's tau), metres.
  double support_distance_m = 0.01;
  /// Normals are estimated from the crop over this radius when the crop comes without them, metres.
  double normal_radius_m = 0.012;
  /// The analysis, the probe and the refinement use every k-th crop point, k chosen to keep at most
  /// this many (shares and a 6x6 system need no more; a table top's crop has tens of thousands).
  int max_points = 3000;
  /// Gauss-Newton iterations of the point-to-plane refinement (RefinePointToPlane); 0: none.
  int refine_iterations = 10;
  /// The refinement stops once a step moves the pose less than this, in translation and in rotation
  /// (arc at the crop's radius), metres: a hundredth of the depth's noise. Much less keeps the robust
  /// fit reweighting for all its iterations after it has converged.
  double refine_step_m = 1e-5;
  /// The same stop for the polish along probed directions (RefinePointToPlane given `probed`), metres.
  /// Those directions are known to millimetres, and the robust kernel's reweighting keeps moving them by
  /// tens of micrometres a step: at refine_step_m a fifth of the demo's polishes ran all their steps.
  double polish_step_m = 1e-4;
  /// Residuals are weighted by a Geman-McClure kernel at this many robust standard deviations (MAD) of
  /// the residuals, so points of something else on the object's surface (fingers holding it) do not
  /// pull the estimate; 0: plain least squares.
  double robust_sigmas = 3.0;
  void check() const;
};

struct Observability {
  bool analysed = false;       ///< false: too few supported points; every direction taken as observable
  int supported_points = 0;
  double residual_rms_m = 0.0;  ///< point-to-plane residual RMS of the supported points
  int observable = 6;          ///< directions judged (by their information or by the probe)
  /// Eigenvalues (per supported point, ascending) and eigenvectors (columns) of A, in the object frame
  /// about `center_object`, rotation part scaled by `radius_m`.
  Eigen::Matrix<double, 6, 1> information = Eigen::Matrix<double, 6, 1>::Ones();
  Eigen::Matrix<double, 6, 6> directions = Eigen::Matrix<double, 6, 6>::Identity();
  std::array<bool, 6> judged = {true, true, true, true, true, true};  ///< per direction: observable
  /// Per probed direction (information below min_information), the share of supported points a probe
  /// move lost; -1 when not probed.
  std::array<double, 6> probe_loss = {-1, -1, -1, -1, -1, -1};
  Eigen::Vector3d center_object = Eigen::Vector3d::Zero();
  double radius_m = 1.0;
  /// The unobservable directions in words, object frame ("translation along any direction normal to
  /// (0.00, 0.00, 1.00)", "rotation about (0.00, 0.00, 1.00)"); empty when all six are observable.
  std::vector<std::string> unobservable;
};

/// The analysis at T_camera_object for the crop seen from there (normals estimated when it has none)
/// against the scene index (camera frame); directions below min_information are probed with crops from
/// `model` (the frame's crop source) and judged observable when the probe loses support. A caller that
/// holds a crop taken within a refinement step of T_camera_object passes it as `crop_near_pose` (what a
/// millimetre's move changes in a crop is a few points at its outline), saving two crops.
Observability AnalyseObservability(const CropSource& model, const Rigid3d& T_camera_object, const PointGrid& scene_camera,
                                   const ObservabilityOptions& options, const ModelCrop* crop_near_pose = nullptr);
/// The same from an analysis of the normal equations already made at (within refine_step_m of)
/// T_camera_object with `crop` (a converged RefinePointToPlane's): only the probe and the summary run.
Observability ProbeObservability(const CropSource& model, const ModelCrop& crop, const Rigid3d& T_camera_object,
                                 const PointGrid& scene_camera, const ObservabilityOptions& options, Observability analysed);

/// Point-to-plane refinement of an estimate (Chen & Medioni), moving it only in the directions with
/// information above min_information: point-to-point ICP creeps along weakly constrained directions (a table seen with one edge),
/// point-to-plane converges there in a few steps, and its normal equations are the ones analysed above.
struct PlaneRefinement {
  Rigid3d T_camera_object;
  Observability observability;  ///< at the last iteration's start
  int iterations = 0;
  double rmse_m = 0.0;  ///< point-to-plane residual RMS at the last iteration's start
  /// The last step moved less than refine_step_m: `observability` holds the equations at the result.
  bool converged = false;
};
/// `first_gate_m`: the correspondence gate of the first iteration (a tracking prediction may be a
/// centimetre or two off); later ones use options.support_distance_m. `probed`: an analysis at (or
/// near) the start; the weak directions its probe found observable are refined too (their part of the
/// Gauss-Newton step), so that only truly unobservable directions keep their start.
PlaneRefinement RefinePointToPlane(const ModelCrop& crop, const Rigid3d& T_camera_object_init,
                                   const PointGrid& scene_camera, const ObservabilityOptions& options,
                                   double first_gate_m = 0.0, const Observability* probed = nullptr);

/// The crop's normals (object frame): its own, or estimated within `radius_m` and turned toward the
/// camera at T_camera_object.
PointCloud NormalsOf(const ModelCrop& crop, const Rigid3d& T_camera_object, double radius_m);

/// A crop point (its index) matched to a scene point (camera frame).
using CropMatch = std::pair<size_t, Eigen::Vector3d>;

/// Every k-th crop point (k keeping at most `max_points`) with its nearest scene point within `gate_m`.
std::vector<CropMatch> MatchCrop(const PointCloud& points_model, const Rigid3d& T_camera_object, const PointGrid& scene_camera,
                                 double gate_m, int max_points);

/// The origin and scale of the analysis coordinates over matched crop points: their centroid (object
/// frame) and RMS radius from it (at least 1 mm). Precondition: `matches` is not empty.
std::pair<Eigen::Vector3d, double> AnalysisCentre(const PointCloud& points_model, const std::vector<CropMatch>& matches);

/// The point-to-plane row of model point `p` with normal `n` (object frame) in the analysis coordinates
/// about `center`, the rotation part scaled by `radius_m`: [L w; v] as Observability::directions and
/// MovedAlong read them.
inline Eigen::Matrix<double, 6, 1> AnalysisRow(const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                                               const Eigen::Vector3d& center, double radius_m) {
  Eigen::Matrix<double, 6, 1> row;
  row << (p - center).cross(n) / radius_m, n;
  return row;
}

/// The judged columns of `o.directions`, in order.
Eigen::Matrix<double, 6, Eigen::Dynamic> JudgedDirections(const Observability& o);

/// True when the probe, not the normals, made some direction of `o` observable (its information is weak
/// but moving along it loses the outline's support): those are the ones RefinePointToPlane's `probed`
/// pass moves along.
bool HasProbedDirections(const Observability& o);

/// The pose moved by `step` ([L w; v], object frame about `center`, rotation scaled by `radius_m`: the
/// analysis coordinates of Observability::directions).
Rigid3d MovedAlong(const Rigid3d& T_camera_object, const Eigen::Matrix<double, 6, 1>& step,
                   const Eigen::Vector3d& center, double radius_m);

/// Sets `observable` and the `unobservable` sentences from `judged` and `directions` (after the
/// directions were expressed in another object frame, as ApplySymmetry does).
void SummariseObservability(Observability* o);

/// Takes direction `u` (analysis coordinates: rotation scaled by radius_m, then translation) out of the
/// judged ones: the judged subspace loses u's part in it, and what is left is re-expressed in the
/// eigen-directions of the information restricted to it. For a measurement the depth makes but cannot be
/// trusted in (a time-of-flight camera's range to a reflective surface: label_check.h LeaveOutRange).
/// No change when `o` was not analysed or u is already unjudged. The columns then hold the unjudged
/// directions first (u's last), then the judged ones by ascending information.
void LeaveOutDirection(Observability* o, const Eigen::Matrix<double, 6, 1>& u);

/// The difference of `label` from `estimate` (both T_camera_object) restricted to the observable
/// directions: translation of the analysis centre (mm) and rotation (deg).
struct ObservedDifference {
  double position_mm = 0.0;
  double rotation_deg = 0.0;
};
ObservedDifference ObservedPart(const Observability& observability, const Rigid3d& estimate, const Rigid3d& label);

/// One standard deviation of an estimate in its observable directions, from the point-to-plane normal
/// equations: a least-squares estimate with residual RMS s over n supported points has covariance
/// s^2 (n A)^-1 (A per point), here summed over the observable eigen-directions only. Neighbouring crop
/// points share the sensor's noise and the scene's voxel (their residuals are correlated), so n is
/// divided by `points_per_residual`. `point_object`: where the position is taken (the analysis centre
/// for an observed difference, the object origin for the whole one). Zeros when not analysed.
struct EstimatePrecision {
  double position_mm = 0.0;
  double rotation_deg = 0.0;
};
EstimatePrecision PrecisionOf(const Observability& observability, const Eigen::Vector3d& point_object,
                              double points_per_residual);

}  // namespace mocap
