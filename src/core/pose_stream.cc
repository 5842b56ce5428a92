#include "core/pose_stream.h"

#include <algorithm>
#include <array>

#include "core/check.h"

namespace mocap {
namespace {

constexpr std::array<std::string_view, 5> kStatusNames = {"valid", "missing", "disabled", "out_of_volume",
                                                         "partially_in_volume"};

InterpolatedPose Failed(InterpolationFailure failure) {
  InterpolatedPose out;
  out.failure = failure;
  return out;
}

}  // namespace

std::string_view ToString(PoseStatus status) { return kStatusNames.at(static_cast<size_t>(status)); }

PoseStatus PoseStatusFromString(std::string_view name) {
  for (size_t i = 0; i < kStatusNames.size(); ++i)
    if (kStatusNames[i] == name) return static_cast<PoseStatus>(i);
  throw InputError("", Str("unknown tracker status '", name, "' (expected valid, missing, disabled, ",
                           "out_of_volume or partially_in_volume)"));
}

bool HasPose(PoseStatus status) {
  return status == PoseStatus::kValid || status == PoseStatus::kPartiallyInVolume;
}

void InterpolationOptions::check() const {
  if (max_gap_ns <= 0) throw InputError("InterpolationOptions", "max_gap_ns must be positive");
  if (max_extrapolation_ns < 0) throw InputError("InterpolationOptions", "max_extrapolation_ns must be >= 0");
}

std::string_view ToString(InterpolationFailure failure) {
  switch (failure) {
    case InterpolationFailure::kNone: return "none";
    case InterpolationFailure::kEmptyStream: return "empty_stream";
    case InterpolationFailure::kBeforeStart: return "before_start";
    case InterpolationFailure::kAfterEnd: return "after_end";
    case InterpolationFailure::kGapTooLong: return "gap_too_long";
    case InterpolationFailure::kNeighbourInvalid: return "neighbour_invalid";
  }
  return "unknown";
}

std::string InterpolatedPose::reason() const {
  switch (failure) {
    case InterpolationFailure::kNone: return "ok";
    case InterpolationFailure::kGapTooLong:
      return Str("tracker gap of ", static_cast<double>(gap_ns) * 1e-6, " ms around the frame is too long");
    case InterpolationFailure::kNeighbourInvalid:
      return Str("a neighbouring tracker sample is ", ToString(neighbour_status));
    default: return std::string(ToString(failure));
  }
}

InterpolatedPose InterpolatePose(std::span<const PoseSample> samples, int64_t stamp_ns,
                                 const InterpolationOptions& options) {
  if (samples.empty()) return Failed(InterpolationFailure::kEmptyStream);
  const auto after = std::upper_bound(samples.begin(), samples.end(), stamp_ns,
                                      [](int64_t t, const PoseSample& s) { return t < s.stamp_ns; });
  // `at` is the last sample with stamp <= query (snapping to the ends within max_extrapolation_ns).
  const PoseSample* at = nullptr;
  const PoseSample* next = nullptr;
  if (after == samples.begin()) {
    if (samples.front().stamp_ns - stamp_ns > options.max_extrapolation_ns) return Failed(InterpolationFailure::kBeforeStart);
    at = &samples.front();
  } else {
    at = &*(after - 1);
    if (after != samples.end()) next = &*after;
  }
  if (next == nullptr && stamp_ns - at->stamp_ns > options.max_extrapolation_ns)
    return Failed(InterpolationFailure::kAfterEnd);

  InterpolatedPose out;
  out.before_ns = at->stamp_ns;
  const bool exact = next == nullptr || at->stamp_ns == stamp_ns;
  if (!exact) {
    out.after_ns = next->stamp_ns;
    out.gap_ns = next->stamp_ns - at->stamp_ns;
  } else {
    out.after_ns = at->stamp_ns;
  }
  for (const PoseSample* s : {at, exact ? at : next}) {
    if (!HasPose(s->status)) {
      out.failure = InterpolationFailure::kNeighbourInvalid;
      out.neighbour_status = s->status;
      return out;
    }
  }
  if (out.gap_ns > options.max_gap_ns) {
    out.failure = InterpolationFailure::kGapTooLong;
    return out;
  }
  if (exact) {
    out.pose = at->pose;
  } else {
    const double alpha = static_cast<double>(stamp_ns - at->stamp_ns) / static_cast<double>(out.gap_ns);
    out.pose = Interpolate(at->pose, next->pose, alpha);
  }
  return out;
}

}  // namespace mocap
