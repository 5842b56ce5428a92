#pragma once
// What `calibrate check` reads of a validation: the records with a reliable estimate, each as the pair
// (label, SegICP estimate) the calibration check compares (calibrate/calibration_check.h). One
// conversion for the CLI and the accuracy sweep.
#include <vector>

#include "calibrate/calibration_check.h"
#include "validate/session_check.h"

namespace mocap::pipeline {

/// The records with a reliable estimate. A body of revolution (the continuous symmetry the validator
/// compares modulo) gets its spin axis. A label moved to its depth's exposure (a Kinect v2:
/// validate/depth_time.h) is stamped at that exposure, the time both poses of the pair are at.
std::vector<CheckRecord> CalibrationCheckRecords(const std::vector<RecordCheck>& records,
                                                 const std::vector<ValidationObject>& objects);

}  // namespace mocap::pipeline
