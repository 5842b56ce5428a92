#include "validate/observability.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <tuple>

#include "core/check.h"
#include "validate/crop_cache.h"
#include "validate/search_memory.h"

namespace mocap {
namespace {

std::string Direction(const Eigen::Vector3d& d) {
  char text[64];
  std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f)", d.x() + 0.0, d.y() + 0.0, d.z() + 0.0);
  return text;
}

/// An orthonormal basis (columns) of the span of `vectors`, by SVD (rank by a relative tolerance).
Eigen::MatrixXd Span(const std::vector<Eigen::Vector3d>& vectors) {
  if (vectors.empty()) return Eigen::MatrixXd(3, 0);
  Eigen::MatrixXd M(3, static_cast<Eigen::Index>(vectors.size()));
  for (size_t i = 0; i < vectors.size(); ++i) M.col(static_cast<Eigen::Index>(i)) = vectors[i];
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullU);
  int rank = 0;
  for (Eigen::Index i = 0; i < svd.singularValues().size(); ++i) rank += svd.singularValues()(i) > 0.3;
  return svd.matrixU().leftCols(rank);
}

/// One phrase per kind of motion: "translation along d", "... within the plane normal to n", "... in
/// every direction"; the same for rotation (about the analysis centre).
void Describe(const std::vector<Eigen::Vector3d>& motions, const char* kind, const char* preposition,
              std::vector<std::string>* out) {
  const Eigen::MatrixXd basis = Span(motions);
  if (basis.cols() == 1) out->push_back(Str(kind, " ", preposition, " ", Direction(basis.col(0))));
  if (basis.cols() == 2)
    out->push_back(Str(kind, " ", preposition, " any direction normal to ",
                       Direction(Eigen::Vector3d(basis.col(0)).cross(Eigen::Vector3d(basis.col(1))).normalized())));
  if (basis.cols() == 3) out->push_back(Str(kind, " in every direction"));
}

}  // namespace

/// Geman-McClure weights of point-to-plane residuals `r`, at `sigmas` times their robust spread (MAD),
/// no narrower than `min_scale_m`; all ones for sigmas = 0 (least squares). A hand holding an object
/// puts finger points a centimetre or two in front of its surface and inside its mask (the labeller's
/// visibility tolerance is about 2 cm): at full weight they turned a carried bottle 2 deg about its axis.
std::vector<double> RobustWeights(const std::vector<double>& r, double sigmas, double min_scale_m) {
  std::vector<double> w(r.size(), 1.0);
  if (sigmas <= 0 || r.empty()) return w;
  std::vector<double> magnitude(r.size());
  for (size_t i = 0; i < r.size(); ++i) magnitude[i] = std::abs(r[i]);
  std::nth_element(magnitude.begin(), magnitude.begin() + static_cast<std::ptrdiff_t>(magnitude.size() / 2), magnitude.end());
  const double c = sigmas * std::max(min_scale_m, 1.4826 * magnitude[magnitude.size() / 2]);
  for (size_t i = 0; i < r.size(); ++i) {
    const double u = 1.0 + (r[i] / c) * (r[i] / c);
    w[i] = 1.0 / (u * u);
  }
  return w;
}

void ObservabilityOptions::check() const {
  if (!(min_information > 0 && min_information < 1)) throw InputError("ObservabilityOptions", "min_information must lie in (0, 1)");
  if (!(probe_m > 0)) throw InputError("ObservabilityOptions", "probe_m must be positive");
  if (!(probe_support_m > 0)) throw InputError("ObservabilityOptions", "probe_support_m must be positive");
  if (!(probe_min_loss > 0 && probe_min_loss < 1)) throw InputError("ObservabilityOptions", "probe_min_loss must lie in (0, 1)");
  if (probe_min_lost_points < 0) throw InputError("ObservabilityOptions", "probe_min_lost_points must be >= 0");
  if (!(support_distance_m > 0)) throw InputError("ObservabilityOptions", "support_distance_m must be positive");
  if (!(normal_radius_m > 0)) throw InputError("ObservabilityOptions", "normal_radius_m must be positive");
  if (refine_iterations < 0) throw InputError("ObservabilityOptions", "refine_iterations must be >= 0");
  if (!(refine_step_m > 0) || !(polish_step_m > 0))
    throw InputError("ObservabilityOptions", "refine_step_m and polish_step_m must be positive");
  if (max_points < 100) throw InputError("ObservabilityOptions", "max_points must be >= 100");
  if (!(robust_sigmas >= 0 && robust_sigmas <= 100)) throw InputError("ObservabilityOptions", "robust_sigmas must lie in [0, 100]");
}

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// Point-to-plane normal equations at T_camera_object over the supported crop points: A and b of the
/// residuals n.(T p - s) (camera frame), per point, about the supported points' centroid.
struct NormalEquations {
  Matrix6d A = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius_m = 1.0;
  int supported = 0;
  double rmse_m = 0.0;  ///< of the point-to-plane residuals
};

/// Every k-th index of n, k keeping at most max_points.
size_t Stride(size_t n, int max_points) { return std::max<size_t>(1, (n + static_cast<size_t>(max_points) - 1) / static_cast<size_t>(max_points)); }

/// How many of n indices that stride visits.
size_t SampledCount(size_t n, int max_points) {
  const size_t stride = Stride(n, max_points);
  return (n + stride - 1) / stride;
}

/// `searches`: one memory per crop point, kept over a refinement's iterations (validate/search_memory.h),
/// or null for a one-off analysis.
NormalEquations Build(const PointCloud& points, const PointCloud& normals, const Rigid3d& T_camera_object,
                      const PointGrid& scene, double gate_m, int max_points, double robust_sigmas,
                      std::vector<SearchMemory>* searches = nullptr) {
  NormalEquations e;
  std::vector<CropMatch> matches;
  if (searches) {
    for (size_t i = 0; i < points.size(); i += Stride(points.size(), max_points)) {
      SearchMemory& last = (*searches)[i];
      double distance_sq = 0;
      // From scratch when it must search: between equidistant points it then answers as Nearest does.
      if (NearestRemembered(scene, T_camera_object * points[i], gate_m, &last, &distance_sq, false))
        matches.emplace_back(i, scene.point(last.match));
    }
  } else {
    matches = MatchCrop(points, T_camera_object, scene, gate_m, max_points);
  }
  e.supported = static_cast<int>(matches.size());
  if (matches.empty()) return e;
  std::tie(e.center, e.radius_m) = AnalysisCentre(points, matches);
  const Eigen::Matrix3d R = T_camera_object.rotation_matrix();
  std::vector<double> residuals;
  residuals.reserve(matches.size());
  for (const auto& [i, s] : matches) residuals.push_back((R * normals[i]).dot(T_camera_object * points[i] - s));
  const std::vector<double> weights = RobustWeights(residuals, robust_sigmas, kMinRobustScaleM);
  double weight_sum = 0;
  for (size_t m = 0; m < matches.size(); ++m) {
    const size_t i = matches[m].first;
    const Vector6d J = AnalysisRow(points[i], normals[i], e.center, e.radius_m);
    const double r = residuals[m], w = weights[m];
    // The upper half of A += w J J^T (the lower half is filled once, below), in the arithmetic of Eigen's
    // rankUpdate, which the compiler kept as a call per point.
    for (int col = 0; col < 6; ++col) {
      const double w_j = w * J(col);
      for (int row = 0; row <= col; ++row) e.A(row, col) += w_j * J(row);
    }
    e.b += w * J * r;
    e.rmse_m += w * r * r;
    weight_sum += w;
  }
  // Weighted means: the information per supported point and the residual RMS of the points kept.
  e.rmse_m = std::sqrt(e.rmse_m / weight_sum);
  const Matrix6d upper = e.A;
  e.A = upper.selfadjointView<Eigen::Upper>();
  e.A /= weight_sum;
  e.b /= weight_sum;
  return e;
}

/// The eigen-analysis of equations `e`: directions judged by their information alone.
Observability Analyse(const NormalEquations& e, const ObservabilityOptions& options) {
  Observability out;
  out.supported_points = e.supported;
  out.residual_rms_m = e.rmse_m;
  if (e.supported < 10) return out;
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(e.A);
  out.analysed = true;
  out.information = eig.eigenvalues();
  out.directions = eig.eigenvectors();
  out.center_object = e.center;
  out.radius_m = e.radius_m;
  for (int k = 0; k < 6; ++k) out.judged[k] = out.information(k) >= options.min_information;
  return out;
}


/// Share of `crop` points (at T) with a scene point within `gate_m`.
double SupportedShare(const PointCloud& crop_model, const Rigid3d& T_camera_object, const PointGrid& scene, double gate_m,
                      int max_points) {
  if (crop_model.empty()) return 0.0;
  int supported = 0;
  for (size_t i = 0; i < crop_model.size(); i += Stride(crop_model.size(), max_points))
    supported += scene.AnyWithin(T_camera_object * crop_model[i], gate_m);
  return static_cast<double>(supported) / static_cast<double>(SampledCount(crop_model.size(), max_points));
}

/// Probes every direction not judged by its information: both ways, the larger loss counts.
void Probe(const CropSource& model, const ModelCrop& crop, const Rigid3d& T_camera_object, const PointGrid& scene,
           const ObservabilityOptions& options, Observability* o) {
  const double base = SupportedShare(crop.points_model, T_camera_object, scene, options.probe_support_m, options.max_points);
  // The shares are over this many crop points (SupportedShare's).
  const double sampled = static_cast<double>(SampledCount(crop.points_model.size(), options.max_points));
  for (int k = 0; k < 6; ++k) {
    if (o->judged[k]) continue;
    double loss = 0.0;
    for (const double sign : {1.0, -1.0}) {
      const Rigid3d moved = MovedAlong(T_camera_object, sign * options.probe_m * o->directions.col(k), o->center_object, o->radius_m);
      loss = std::max(loss, base - SupportedShare(model.CropPoints(moved).points_model, moved, scene, options.probe_support_m,
                                                  options.max_points));
    }
    o->probe_loss[k] = loss;
    o->judged[k] = loss >= options.probe_min_loss && loss * sampled >= options.probe_min_lost_points;
  }
}

}  // namespace

PointCloud NormalsOf(const ModelCrop& crop, const Rigid3d& T_camera_object, double radius_m) {
  if (crop.normals_model.size() == crop.points_model.size()) return crop.normals_model;
  return EstimateNormals(crop.points_model, radius_m, T_camera_object.inverse().translation());
}

std::vector<CropMatch> MatchCrop(const PointCloud& points_model, const Rigid3d& T_camera_object, const PointGrid& scene_camera,
                                 double gate_m, int max_points) {
  std::vector<CropMatch> matches;
  for (size_t i = 0; i < points_model.size(); i += Stride(points_model.size(), max_points)) {
    size_t index = 0;
    double distance_sq = 0;
    if (scene_camera.Nearest(T_camera_object * points_model[i], gate_m, &index, &distance_sq))
      matches.emplace_back(i, scene_camera.point(index));
  }
  return matches;
}

std::pair<Eigen::Vector3d, double> AnalysisCentre(const PointCloud& points_model, const std::vector<CropMatch>& matches) {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (const auto& [i, s] : matches) center += points_model[i];
  center /= static_cast<double>(matches.size());
  double radius_sq = 0;
  for (const auto& [i, s] : matches) radius_sq += (points_model[i] - center).squaredNorm();
  return {center, std::max(1e-3, std::sqrt(radius_sq / static_cast<double>(matches.size())))};
}

Eigen::Matrix<double, 6, Eigen::Dynamic> JudgedDirections(const Observability& o) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> judged(6, std::count(o.judged.begin(), o.judged.end(), true));
  for (int k = 0, column = 0; k < 6; ++k)
    if (o.judged[k]) judged.col(column++) = o.directions.col(k);
  return judged;
}

Observability AnalyseObservability(const CropSource& model, const Rigid3d& T_camera_object, const PointGrid& scene_camera,
                                   const ObservabilityOptions& options, const ModelCrop* crop_near_pose) {
  const ModelCrop own = crop_near_pose ? ModelCrop{} : model.Crop(T_camera_object);
  const ModelCrop& crop = crop_near_pose ? *crop_near_pose : own;
  const PointCloud normals = NormalsOf(crop, T_camera_object, options.normal_radius_m);
  return ProbeObservability(model, crop, T_camera_object, scene_camera, options,
                            Analyse(Build(crop.points_model, normals, T_camera_object, scene_camera,
                                          options.support_distance_m, options.max_points, options.robust_sigmas),
                                    options));
}

Observability ProbeObservability(const CropSource& model, const ModelCrop& crop, const Rigid3d& T_camera_object,
                                 const PointGrid& scene_camera, const ObservabilityOptions& options, Observability analysed) {
  if (analysed.analysed) {
    Probe(model, crop, T_camera_object, scene_camera, options, &analysed);
    SummariseObservability(&analysed);
  }
  return analysed;
}

namespace {

/// The projector onto the directions `probed` found observable by the probe alone (weak information,
/// but moving along them loses the outline's support): a body nearly of revolution, such as a bottle,
/// is told apart from its turned self by a few features, so its spin is weak yet observable.
bool IsProbedDirection(const Observability& o, int k) { return o.analysed && o.judged[k] && o.probe_loss[k] >= 0; }

std::optional<Matrix6d> ProbedProjector(const Observability* probed) {
  if (!probed || !HasProbedDirections(*probed)) return std::nullopt;
  Matrix6d P = Matrix6d::Zero();
  for (int k = 0; k < 6; ++k)
    if (IsProbedDirection(*probed, k)) P += probed->directions.col(k) * probed->directions.col(k).transpose();
  return P;
}

}  // namespace

bool HasProbedDirections(const Observability& o) {
  for (int k = 0; k < 6; ++k)
    if (IsProbedDirection(o, k)) return true;
  return false;
}

Rigid3d MovedAlong(const Rigid3d& T_camera_object, const Vector6d& step, const Eigen::Vector3d& center, double radius_m) {
  const Eigen::Vector3d w = step.head<3>() / radius_m, v = step.tail<3>();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(w.norm(), w.norm() > 0 ? w.normalized() : Eigen::Vector3d::UnitX())
                                .toRotationMatrix();
  return T_camera_object * Rigid3d(R, center - R * center + v);  // p -> c + R (p - c) + v
}

PlaneRefinement RefinePointToPlane(const ModelCrop& crop, const Rigid3d& T_camera_object_init,
                                   const PointGrid& scene_camera, const ObservabilityOptions& options,
                                   double first_gate_m, const Observability* probed) {
  const std::optional<Matrix6d> probed_move = ProbedProjector(probed);
  const PointCloud normals = NormalsOf(crop, T_camera_object_init, options.normal_radius_m);
  PlaneRefinement out;
  out.T_camera_object = T_camera_object_init;
  Vector6d weak_moved = Vector6d::Zero();  // along the probed directions, [L w; v] metres
  // Late iterations move the pose by micrometres: most points keep their match without a search.
  std::vector<SearchMemory> searches(crop.points_model.size());
  for (int iteration = 0; iteration < options.refine_iterations; ++iteration) {
    const double gate_m = iteration == 0 ? std::max(first_gate_m, options.support_distance_m) : options.support_distance_m;
    const NormalEquations e = Build(crop.points_model, normals, out.T_camera_object, scene_camera, gate_m, options.max_points,
                                    options.robust_sigmas, &searches);
    out.observability = Analyse(e, options);
    out.rmse_m = e.rmse_m;
    if (!out.observability.analysed) return out;
    // Gauss-Newton step in the observable directions only: the pose stays where it started along the
    // others (the label, or the acquisition's estimate), rather than drifting on noise.
    Vector6d step = Vector6d::Zero();
    Vector6d weak_step = Vector6d::Zero();
    for (int k = 0; k < 6; ++k) {
      const Vector6d d = out.observability.directions.col(k);
      const double information = out.observability.information(k);
      if (information >= options.min_information)
        step -= d * (d.dot(e.b) / information);
      else if (probed_move && information >= kMinProbedInformation)  // only its part the probe found observable
        weak_step -= *probed_move * d * (d.dot(e.b) / information);
    }
    // Weak directions get a trust region of two probe lengths in all: their Gauss-Newton step divides by
    // little information and would otherwise leap on noise (a table top slid along an edge the probe saw).
    weak_moved += weak_step;
    if (weak_moved.norm() > 2 * options.probe_m) {
      const Vector6d clamped = weak_moved * (2 * options.probe_m / weak_moved.norm());
      weak_step += clamped - weak_moved;
      weak_moved = clamped;
    }
    step += weak_step;
    out.T_camera_object = MovedAlong(out.T_camera_object, step, e.center, e.radius_m);
    out.iterations = iteration + 1;
    const double stop_m = probed_move ? options.polish_step_m : options.refine_step_m;
    out.converged = step.tail<3>().norm() < stop_m && step.head<3>().norm() < stop_m;
    if (out.converged) break;
  }
  return out;
}

ObservedDifference ObservedPart(const Observability& o, const Rigid3d& estimate, const Rigid3d& label) {
  // The motion taking the estimate to the label, in the object frame about the analysis centre.
  const Rigid3d delta = estimate.inverse() * label;
  Eigen::Matrix<double, 6, 1> d;
  d << o.radius_m * delta.rvec(), delta * o.center_object - o.center_object;
  Eigen::Matrix<double, 6, 1> observed = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < 6; ++k)
    if (!o.analysed || o.judged[k]) observed += o.directions.col(k) * o.directions.col(k).dot(d);
  return {1e3 * observed.tail<3>().norm(), DegFromRad(observed.head<3>().norm() / o.radius_m)};
}

EstimatePrecision PrecisionOf(const Observability& o, const Eigen::Vector3d& point_object, double points_per_residual) {
  if (!o.analysed || o.supported_points <= 0) return {};
  const double n = std::max(1.0, o.supported_points / points_per_residual);
  const Eigen::Vector3d lever = point_object - o.center_object;
  double position_var = 0, rotation_var = 0;
  for (int k = 0; k < 6; ++k) {
    if (!o.judged[k]) continue;
    // Variance along direction k; a probe-judged direction has little information, and a large variance.
    const double var = o.residual_rms_m * o.residual_rms_m / (n * std::max(o.information(k), 1e-9));
    const Eigen::Vector3d w = o.directions.col(k).head<3>() / o.radius_m, v = o.directions.col(k).tail<3>();
    position_var += var * (v + w.cross(lever)).squaredNorm();
    rotation_var += var * w.squaredNorm();
  }
  return {1e3 * std::sqrt(position_var), DegFromRad(std::sqrt(rotation_var))};
}

void LeaveOutDirection(Observability* o, const Vector6d& u) {
  if (!o->analysed || !(u.norm() > 0)) return;
  const Matrix6d A = o->directions * o->information.asDiagonal() * o->directions.transpose();
  std::vector<int> unjudged;
  for (int k = 0; k < 6; ++k)
    if (!o->judged[k]) unjudged.push_back(k);
  const Eigen::MatrixXd J = JudgedDirections(*o);
  const Vector6d inside = J * (J.transpose() * u.normalized());
  if (inside.norm() < 1e-6) return;  // u lies in the unjudged directions already
  const Vector6d e = inside.normalized();
  // The judged subspace without e, re-diagonalised in A (PrecisionOf reads information per direction).
  const Eigen::Index m = J.cols() - 1;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J - e * (e.transpose() * J), Eigen::ComputeThinU);
  const Eigen::MatrixXd Q = svd.matrixU().leftCols(m);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(Q.transpose() * A * Q);
  Observability out = *o;
  int column = 0;
  for (int k : unjudged) {
    out.directions.col(column) = o->directions.col(k), out.information(column) = o->information(k);
    out.judged[column] = false, out.probe_loss[column++] = o->probe_loss[k];
  }
  out.directions.col(column) = e, out.information(column) = e.dot(A * e);
  out.judged[column] = false, out.probe_loss[column++] = -1;
  for (Eigen::Index i = 0; i < m; ++i) {
    out.directions.col(column) = Q * eig.eigenvectors().col(i), out.information(column) = eig.eigenvalues()(i);
    out.judged[column] = true, out.probe_loss[column++] = -1;
  }
  SummariseObservability(&out);
  *o = out;
}

void SummariseObservability(Observability* o) {
  o->observable = 0;
  o->unobservable.clear();
  std::vector<Eigen::Vector3d> rotations, translations;
  for (int k = 0; k < 6; ++k) {
    if (o->judged[k]) {
      ++o->observable;
      continue;
    }
    const Vector6d v = o->directions.col(k);
    const bool rotation = v.head<3>().norm() > v.tail<3>().norm();  // mostly a turn, or mostly a shift
    (rotation ? rotations : translations).push_back(rotation ? v.head<3>().normalized() : v.tail<3>().normalized());
  }
  Describe(translations, "translation", "along", &o->unobservable);
  Describe(rotations, "rotation", "about", &o->unobservable);
}

}  // namespace mocap
