#include "pipeline/calibration_records.h"

#include <map>

namespace mocap::pipeline {

std::vector<CheckRecord> CalibrationCheckRecords(const std::vector<RecordCheck>& records,
                                                 const std::vector<ValidationObject>& objects) {
  std::map<int, Eigen::Vector3d> spin_axes;
  for (const ValidationObject& o : objects)
    if (o.symmetry && o.symmetry->step_deg == 0) spin_axes[o.id] = o.symmetry->axis_object;
  std::vector<CheckRecord> out;
  for (const RecordCheck& r : records) {
    if (!r.check.estimated || !r.check.segicp_reliable) continue;
    out.push_back({r.camera, r.name, r.instance, r.stamp_ns + r.label_shift_ns, r.T_camera_object_label,
                   r.check.T_camera_object_segicp});
    if (const auto it = spin_axes.find(r.object); it != spin_axes.end()) out.back().spin_axis_mesh = it->second;
    // Along the directions the depth did not judge the estimate is the label's: no measurement.
    const Observability& o = r.check.observability;
    if (o.analysed && o.observable < 6) out.back().judged = CheckRecord::Judged{JudgedDirections(o), o.center_object, o.radius_m};
  }
  return out;
}

}  // namespace mocap::pipeline
