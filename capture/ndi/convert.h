#pragma once
// NDI units to the project's types, at the edge (DESIGN.md "Conventions"): millimetres become metres,
// the scalar-first quaternion (q0 qx qy qz) becomes a normalised Rigid3d T_tracker_body, and the
// handle status plus port-status bits become a PoseStatus.
#include <optional>
#include <string>

#include "capture/ndi/reply.h"
#include "core/pose_stream.h"
#include "core/rigid3.h"

namespace mocap::ndi {

/// Mapping (docs/ndi.md "Statuses"):
///   DISABLED -> kDisabled; MISSING -> kMissing;
///   a transform with port-status bit 0x40 -> kOutOfVolume, with 0x80 -> kPartiallyInVolume;
///   other transforms -> kValid. A VALID handle without a usable quaternion (NaN, or norm off by more
///   than 10%) -> kMissing.
PoseStatus ToPoseStatus(const HandleReport& report);

/// T_tracker_body in metres, when the report carries a usable transform: finite values and a
/// quaternion norm within 10% of 1 (NDI rounds it; it "may not be normalized"). Normalised here.
std::optional<Rigid3d> ToRigid3d(const HandleReport& report);

/// RMS marker fit error in metres.
inline double RmsErrorM(const HandleReport& report) { return report.rms_error_mm * 1e-3; }

}  // namespace mocap::ndi
