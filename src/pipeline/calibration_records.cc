#include "pipeline/calibration_records.h"

#include <algorithm>
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
    const int judged_count = static_cast<int>(std::count(o.judged.begin(), o.judged.end(), true));
    if (o.analysed && judged_count < 6) {
      CheckRecord::Judged judged{Eigen::Matrix<double, 6, Eigen::Dynamic>(6, judged_count), o.center_object, o.radius_m};
      for (int k = 0, column = 0; k < 6; ++k)
        if (o.judged[k]) judged.directions.col(column++) = o.directions.col(k);
      out.back().judged = judged;
    }
  }
  return out;
}

}  // namespace mocap::pipeline
