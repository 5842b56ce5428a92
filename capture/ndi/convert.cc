#include "capture/ndi/convert.h"

#include <cmath>

namespace mocap::ndi {

std::optional<Rigid3d> ToRigid3d(const HandleReport& report) {
  if (!report.has_transform) return std::nullopt;
  for (double v : report.q_wxyz)
    if (!std::isfinite(v)) return std::nullopt;
  for (double v : report.t_mm)
    if (!std::isfinite(v)) return std::nullopt;
  Eigen::Quaterniond q(report.q_wxyz[0], report.q_wxyz[1], report.q_wxyz[2], report.q_wxyz[3]);
  const double norm = q.norm();
  if (std::abs(norm - 1.0) > 0.1) return std::nullopt;
  q.coeffs() /= norm;
  const Eigen::Vector3d t_m(report.t_mm[0] * 1e-3, report.t_mm[1] * 1e-3, report.t_mm[2] * 1e-3);
  return Rigid3d(q, t_m);
}

PoseStatus ToPoseStatus(const HandleReport& report) {
  switch (report.status) {
    case HandleStatus::kDisabled: return PoseStatus::kDisabled;
    case HandleStatus::kMissing: return PoseStatus::kMissing;
    case HandleStatus::kValid: break;
  }
  if (!ToRigid3d(report)) return PoseStatus::kMissing;
  if (report.port_status & port_status::kOutOfVolume) return PoseStatus::kOutOfVolume;
  if (report.port_status & port_status::kPartiallyInVolume) return PoseStatus::kPartiallyInVolume;
  return PoseStatus::kValid;
}

}  // namespace mocap::ndi
