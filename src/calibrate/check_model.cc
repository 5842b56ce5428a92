#include "calibrate/check_model.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

namespace mocap::check_model {
namespace {

/// E_pred = D * Shift(L, -e) * O against E, scaled by the record's sigmas (see check_model.h).
struct RecordCost {
  explicit RecordCost(const ModelRecord& r) : r_(r) {}

  template <typename T>
  bool operator()(const T* camera, const T* object, const T* latency_s, T* residual) const {
    // Shift(L, -e): the label moved back along its own motion by the latency error.
    const T aa_shift[3] = {-latency_s[0] * r_.w_rad_per_s.x(), -latency_s[0] * r_.w_rad_per_s.y(),
                           -latency_s[0] * r_.w_rad_per_s.z()};
    T q_shift[4], q_label[4] = {T(r_.q_label.w()), T(r_.q_label.x()), T(r_.q_label.y()), T(r_.q_label.z())}, q_ls[4];
    ceres::AngleAxisToQuaternion(aa_shift, q_shift);
    ceres::QuaternionProduct(q_shift, q_label, q_ls);
    T p_mid[3];
    ceres::UnitQuaternionRotatePoint(q_ls, object + 3, p_mid);
    for (int i = 0; i < 3; ++i) p_mid[i] += T(r_.p_label_m(i)) - latency_s[0] * r_.v_m_per_s(i);
    T q_object[4], q_mid[4], q_camera[4], q_pred[4], p_pred[3];
    ceres::AngleAxisToQuaternion(object, q_object);
    ceres::QuaternionProduct(q_ls, q_object, q_mid);
    ceres::AngleAxisToQuaternion(camera, q_camera);
    ceres::QuaternionProduct(q_camera, q_mid, q_pred);
    ceres::UnitQuaternionRotatePoint(q_camera, p_mid, p_pred);
    for (int i = 0; i < 3; ++i) p_pred[i] += camera[3 + i];
    // log(R_E R_pred^T): the segicp quaternion was put in the label's hemisphere when prepared.
    const T q_pred_conj[4] = {q_pred[0], -q_pred[1], -q_pred[2], -q_pred[3]};
    const T q_segicp[4] = {T(r_.q_segicp.w()), T(r_.q_segicp.x()), T(r_.q_segicp.y()), T(r_.q_segicp.z())};
    T q_err[4], aa_err[3];
    ceres::QuaternionProduct(q_segicp, q_pred_conj, q_err);
    ceres::QuaternionToAngleAxis(q_err, aa_err);
    // A body of revolution's spin is the label's by construction: only the tilt of its axis counts.
    const T along = aa_err[0] * r_.spin_axis_camera.x() + aa_err[1] * r_.spin_axis_camera.y() + aa_err[2] * r_.spin_axis_camera.z();
    for (int i = 0; i < 3; ++i) aa_err[i] -= along * r_.spin_axis_camera(i);
    // Only the directions the depth judged are measured.
    T raw[6];
    for (int i = 0; i < 3; ++i) raw[i] = aa_err[i], raw[3 + i] = T(r_.p_segicp_m(i)) - p_pred[i];
    for (int i = 0; i < 6; ++i) {
      T judged = T(0);
      for (int j = 0; j < 6; ++j) judged += r_.judged_part(i, j) * raw[j];
      residual[i] = judged / (i < 3 ? r_.sigma_rad : r_.sigma_m);
    }
    return true;
  }

  ModelRecord r_;
};

using Cost = ceres::AutoDiffCostFunction<RecordCost, 6, 6, 6, 1>;

/// Robust scale of the scaled residual components: 1.4826 * median |r|.
double RobustScale(const std::vector<ModelRecord>& records, const Params& params) {
  std::vector<double> abs;
  for (const ModelRecord& r : records) {
    const Eigen::Matrix<double, 6, 1> e = Residual(r, params);
    for (int i = 0; i < 3; ++i) abs.push_back(std::abs(e(i)) / r.sigma_rad), abs.push_back(std::abs(e(3 + i)) / r.sigma_m);
  }
  if (abs.empty()) return 1;
  const auto mid = abs.begin() + static_cast<std::ptrdiff_t>(abs.size() / 2);
  std::nth_element(abs.begin(), mid, abs.end());
  return std::max(1e-9, 1.4826 * *mid);
}

double* BlockOf(Params& params, const Item& item) {
  if (item.kind == CheckItemKind::kCameraMount) return params.camera[static_cast<size_t>(item.index)].data();
  if (item.kind == CheckItemKind::kObjectMount) return params.object[static_cast<size_t>(item.index)].data();
  return &params.latency_s;
}

/// The first column of an item's parameters within its block.
int FirstColumn(const Item& item) { return item.kind == CheckItemKind::kLatency ? 0 : item.part == Part::kRotation ? 0 : 3; }
int Width(const Item& item) { return item.kind == CheckItemKind::kLatency ? 1 : 3; }

/// (J^T J)^+ of the robustified Jacobian over the free items' parameters (a problem of the same records
/// with every block of a free item fully free, the columns of the held parts then dropped), split per
/// item and scaled by scale^2; empty when J^T J is zero.
std::vector<Eigen::MatrixXd> Covariances(const std::vector<ModelRecord>& records, Params params, const std::vector<Item>& free,
                                         double huber, double scale) {
  ceres::Problem problem;
  for (const ModelRecord& r : records)
    problem.AddResidualBlock(new Cost(new RecordCost(r)), new ceres::HuberLoss(huber), params.camera[static_cast<size_t>(r.camera)].data(),
                             params.object[static_cast<size_t>(r.object)].data(), &params.latency_s);
  ceres::Problem::EvaluateOptions evaluate;
  std::vector<int> columns;
  for (const Item& item : free) {
    double* block = BlockOf(params, item);
    auto at = std::find(evaluate.parameter_blocks.begin(), evaluate.parameter_blocks.end(), block);
    int offset = 0;
    for (auto it = evaluate.parameter_blocks.begin(); it != at; ++it) offset += *it == &params.latency_s ? 1 : 6;
    if (at == evaluate.parameter_blocks.end()) evaluate.parameter_blocks.push_back(block);
    for (int c = 0; c < Width(item); ++c) columns.push_back(offset + FirstColumn(item) + c);
  }
  ceres::CRSMatrix crs;
  if (!problem.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs)) return {};
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, static_cast<Eigen::Index>(columns.size()));
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[static_cast<size_t>(r)]; k < crs.rows[static_cast<size_t>(r) + 1]; ++k)
      for (size_t c = 0; c < columns.size(); ++c)
        if (columns[c] == crs.cols[static_cast<size_t>(k)]) J(r, static_cast<Eigen::Index>(c)) = crs.values[static_cast<size_t>(k)];
  // A pseudo-inverse where a direction no record measures lies within one item (a table's mount slid in
  // its plane, where every record's estimate is the label's): it gets no variance, and SizeOf leaves it
  // out of the item's size. A direction shared by two items (a camera's mount against the one object it
  // sees) leaves both undetermined: no covariance.
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(J.transpose() * J);
  const Eigen::VectorXd& eigen = eig.eigenvalues();
  if (!(eigen.maxCoeff() > 0)) return {};
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(eigen.size());
  for (Eigen::Index i = 0; i < eigen.size(); ++i) {
    if (eigen(i) > 1e-10 * eigen.maxCoeff()) {
      inverse(i) = 1.0 / eigen(i);
      continue;
    }
    int items_in = 0, offset = 0;
    for (const Item& item : free) {
      items_in += eig.eigenvectors().col(i).segment(offset, Width(item)).norm() > 1e-6;
      offset += Width(item);
    }
    if (items_in > 1) return {};
  }
  const Eigen::MatrixXd covariance = eig.eigenvectors() * inverse.asDiagonal() * eig.eigenvectors().transpose() * scale * scale;
  std::vector<Eigen::MatrixXd> out;
  int offset = 0;
  for (const Item& item : free) {
    out.emplace_back(covariance.block(offset, offset, Width(item), Width(item)));
    offset += Width(item);
  }
  return out;
}

/// Holds each block whose items are not all free: constant when none is, its held part when one is.
void HoldFixedParts(ceres::Problem& problem, Params& params, int cameras, int objects, const std::vector<Item>& free) {
  const auto is_free = [&](CheckItemKind kind, int index, Part part) {
    return std::find(free.begin(), free.end(), Item{kind, index, part}) != free.end();
  };
  const auto hold = [&](double* block, CheckItemKind kind, int index) {
    const bool rot = is_free(kind, index, Part::kRotation), trans = is_free(kind, index, Part::kTranslation);
    if (!rot && !trans) problem.SetParameterBlockConstant(block);
    else if (!rot) problem.SetManifold(block, new ceres::SubsetManifold(6, {0, 1, 2}));
    else if (!trans) problem.SetManifold(block, new ceres::SubsetManifold(6, {3, 4, 5}));
  };
  for (int c = 0; c < cameras; ++c) hold(params.camera[static_cast<size_t>(c)].data(), CheckItemKind::kCameraMount, c);
  for (int k = 0; k < objects; ++k) hold(params.object[static_cast<size_t>(k)].data(), CheckItemKind::kObjectMount, k);
  if (!is_free(CheckItemKind::kLatency, 0, Part::kTranslation)) problem.SetParameterBlockConstant(&params.latency_s);
}

}  // namespace

Eigen::Matrix<double, 6, 1> Residual(const ModelRecord& record, const Params& params) {
  Eigen::Matrix<double, 6, 1> scaled;
  const RecordCost cost(record);
  cost(params.camera[static_cast<size_t>(record.camera)].data(),
                     params.object[static_cast<size_t>(record.object)].data(), &params.latency_s, scaled.data());
  scaled.head<3>() *= record.sigma_rad;
  scaled.tail<3>() *= record.sigma_m;
  return scaled;
}

Fit FitItems(const std::vector<ModelRecord>& records, int cameras, int objects, const std::vector<Item>& free, double huber) {
  Fit fit;
  fit.params.camera.assign(static_cast<size_t>(cameras), {0, 0, 0, 0, 0, 0});
  fit.params.object.assign(static_cast<size_t>(objects), {0, 0, 0, 0, 0, 0});
  ceres::Problem problem;
  for (const ModelRecord& r : records)
    problem.AddResidualBlock(new Cost(new RecordCost(r)), new ceres::HuberLoss(huber),
                             fit.params.camera[static_cast<size_t>(r.camera)].data(),
                             fit.params.object[static_cast<size_t>(r.object)].data(), &fit.params.latency_s);
  HoldFixedParts(problem, fit.params, cameras, objects, free);
  if (free.empty()) {
    fit.cost = RobustCost(records, fit.params, huber);
    return fit;
  }
  ceres::Solver::Options options;
  options.max_num_iterations = 50;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.cost = RobustCost(records, fit.params, huber);
  fit.covariance = Covariances(records, fit.params, free, huber, RobustScale(records, fit.params));
  return fit;
}

double RobustCost(const std::vector<ModelRecord>& records, const Params& params, double huber) {
  // Ceres' cost: 0.5 * sum rho(|r|^2), Huber's rho(s) = s below b^2, 2 b sqrt(s) - b^2 above.
  double cost = 0;
  for (const ModelRecord& r : records) {
    Eigen::Matrix<double, 6, 1> e = Residual(r, params);
    e.head<3>() /= r.sigma_rad, e.tail<3>() /= r.sigma_m;
    const double s = e.squaredNorm();
    cost += 0.5 * (s <= huber * huber ? s : 2 * huber * std::sqrt(s) - huber * huber);
  }
  return cost;
}

double CostWithoutItems(const std::vector<ModelRecord>& records, int cameras, int objects, double huber) {
  Params zero;
  zero.camera.assign(static_cast<size_t>(cameras), {0, 0, 0, 0, 0, 0});
  zero.object.assign(static_cast<size_t>(objects), {0, 0, 0, 0, 0, 0});
  return RobustCost(records, zero, huber);
}

}  // namespace mocap::check_model
