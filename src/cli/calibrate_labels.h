#pragma once
// `mocaplabel calibrate object-mount` and `calibrate check`: calibration from a labelled session's
// SegICP estimates (calibrate/object_mount.h, calibrate/calibration_check.h). What they read (the label
// run, its rig and objects as recorded in its run.json, a validation run or a session check run here),
// what they print and the files they write on request.
#include <string>

#include "calibrate/calibration_check.h"
#include "calibrate/object_mount.h"

namespace mocap::cli {

struct LabelsCalibrationArgs {
  std::string session;
  std::string labels;      ///< label run (default SESSION/labels)
  std::string validation;  ///< validation run; object-mount: optional (else the check runs here)
  std::string objects;     ///< default: the label run's objects input, else SESSION/objects.yaml
  std::string rig;         ///< default: the label run's rig input, else the calibration recorded in the session
  std::string object;      ///< object-mount: the object
  int frame_stride = 1;    ///< object-mount without --validation: every Nth frame
  std::string out;         ///< object-mount: objects file to write
  std::string write_rig, write_objects;  ///< check: corrected files to write
  bool force = false, json = false;
};

int CalibrateObjectMountFromLabels(const LabelsCalibrationArgs& args, const ObjectMountOptions& options);
int CheckCalibrationOfLabels(const LabelsCalibrationArgs& args, const CalibrationCheckOptions& options);

}  // namespace mocap::cli
