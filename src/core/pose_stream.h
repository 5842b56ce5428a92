#pragma once
// A stream of timed poses of one tracked body, and its interpolation at a query time.
// Missing data is explicit (DESIGN.md): a sample carries its status, and interpolation refuses, with a
// reason, rather than bridge an invalid neighbour or a long gap.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "core/rigid3.h"

namespace mocap {

/// Tracker status of one body in one sample (NDI: valid / missing / disabled; port status carries
/// out-of-volume and partially-in-volume, which still give a pose).
enum class PoseStatus : uint8_t { kValid = 0, kMissing = 1, kDisabled = 2, kOutOfVolume = 3, kPartiallyInVolume = 4 };

std::string_view ToString(PoseStatus status);
/// Throws InputError for an unknown name.
PoseStatus PoseStatusFromString(std::string_view name);
/// True when the sample holds a usable pose (valid or partially in volume).
bool HasPose(PoseStatus status);

struct PoseSample {
  int64_t stamp_ns = 0;  ///< on the host clock
  PoseStatus status = PoseStatus::kValid;
  Rigid3d pose;  ///< T_tracker_body; meaningful only when HasPose(status)
};

struct InterpolationOptions {
  /// Longest span between the two bracketing samples that is bridged (ns). A tracker at 100 Hz has
  /// 10 ms; one or two lost frames stay within the default, a real dropout does not.
  int64_t max_gap_ns = 50'000'000;
  /// A query this close to the first or last sample snaps to it (ns); beyond, it is outside the stream.
  int64_t max_extrapolation_ns = 0;
  void check() const;
};

enum class InterpolationFailure : uint8_t {
  kNone = 0,
  kEmptyStream,
  kBeforeStart,
  kAfterEnd,
  kGapTooLong,
  kNeighbourInvalid,
};
std::string_view ToString(InterpolationFailure failure);

struct InterpolatedPose {
  std::optional<Rigid3d> pose;  ///< set when failure == kNone
  InterpolationFailure failure = InterpolationFailure::kNone;
  int64_t gap_ns = 0;           ///< span between the bracketing samples (0 on an exact hit)
  int64_t before_ns = 0;        ///< stamp of the sample at or before the query, when there is one
  int64_t after_ns = 0;         ///< stamp of the sample after the query, when there is one
  PoseStatus neighbour_status = PoseStatus::kValid;  ///< the offending status for kNeighbourInvalid
  bool ok() const { return failure == InterpolationFailure::kNone; }
  /// One line for logs and flags, e.g. "gap of 612.3 ms exceeds 50.0 ms".
  std::string reason() const;
};

/// Interpolates T_tracker_body at `stamp_ns`: linear translation, SLERP rotation (Interpolate()).
/// Precondition: `samples` sorted by stamp_ns (equal stamps allowed: the later one wins).
InterpolatedPose InterpolatePose(std::span<const PoseSample> samples, int64_t stamp_ns,
                                 const InterpolationOptions& options = {});

}  // namespace mocap
