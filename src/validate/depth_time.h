#pragma once
// Label poses at the depth's exposure. A Kinect v2 exposes its colour some 15 ms after its depth and the
// capture pairs the two into one record (CameraFrameRecord::depth_stamp_ns). Labels are at the colour's
// exposure, so on a moving object (or camera) the depth disagrees with a correct label by the motion in
// between: 15 ms of a 0.3 m/s carry is 4.5 mm, the size of the errors the check must catch. The check
// therefore compares the depth with the label moved to the depth's time along the instance's labels of
// the neighbouring frames. An error of the calibration (mount, latency) is in every label alike and so
// stays in the moved label: what is checked is still the labelling chain.
#include <cstdint>
#include <vector>

#include "session/reader.h"
#include "validate/session_check.h"

namespace mocap {

struct DepthTimeOptions {
  /// Neighbouring labels farther apart than this are not interpolated between (a gap in the labels or
  /// the tracking); the record is then checked at the colour's time and counted as not moved.
  int64_t max_label_gap_ns = 100'000'000;
  void check() const;  ///< throws InputError
};

/// What MoveLabelsToDepthTime did.
struct DepthTimeMoves {
  int64_t moved = 0;      ///< records whose label pose was moved to the depth's exposure
  int64_t unmovable = 0;  ///< records of depth taken apart whose instance had no label on the far side
};

/// For each record of a frame whose depth was taken apart from its colour, replaces
/// T_camera_object_label by the pose at the depth's exposure, interpolated (core Interpolate) between
/// the record's label and the same instance's label of the frame on the depth's side, and sets
/// label_shift_ns; sets depth_offset_ns (depth minus colour time) of every record. Records of frames
/// without a depth_stamp_ns are untouched.
DepthTimeMoves MoveLabelsToDepthTime(const SessionReader& session, std::vector<RecordCheck>& records,
                                     const DepthTimeOptions& options = {});


}  // namespace mocap
