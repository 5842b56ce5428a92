#include "capture/ndi/recorded_trajectory.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "capture/ndi/reply.h"
#include "core/check.h"

namespace mocap::ndi {
namespace {

uint32_t VolumeBits(PoseStatus status) {
  if (status == PoseStatus::kOutOfVolume) return port_status::kOutOfVolume;
  if (status == PoseStatus::kPartiallyInVolume) return port_status::kPartiallyInVolume;
  return 0;
}

// Out of volume still reports a transform (the tracker flags it); missing and disabled do not.
bool ReportsPose(PoseStatus status) { return status != PoseStatus::kMissing && status != PoseStatus::kDisabled; }

// The sample whose stamp is closest to `stamp_ns` (the later one on a tie). Precondition: not empty.
const PoseSample& Nearest(const std::vector<PoseSample>& samples, int64_t stamp_ns) {
  auto after = std::lower_bound(samples.begin(), samples.end(), stamp_ns,
                                [](const PoseSample& s, int64_t t) { return s.stamp_ns < t; });
  if (after == samples.end()) return samples.back();
  if (after == samples.begin()) return *after;
  const auto before = std::prev(after);
  return stamp_ns - before->stamp_ns < after->stamp_ns - stamp_ns ? *before : *after;
}

}  // namespace

void RecordedTrajectoryOptions::check() const {
  interpolation.check();
  if (hold_ns < 0) throw InputError("recorded trajectory", "hold_ns must not be negative");
}

RecordedTrajectory::RecordedTrajectory(std::vector<RecordedBody> bodies, const RecordedTrajectoryOptions& options)
    : bodies_(std::move(bodies)), options_(options) {
  options_.check();
  if (bodies_.empty()) throw InputError("recorded trajectory", "has no bodies");
  std::set<std::string> names;
  for (const RecordedBody& body : bodies_) {
    if (body.name.empty()) throw InputError("recorded trajectory", "a body has no name");
    if (!names.insert(body.name).second) throw InputError("recorded trajectory", "body '" + body.name + "' appears twice");
    const auto unsorted = std::is_sorted_until(body.samples.begin(), body.samples.end(),
                                               [](const PoseSample& a, const PoseSample& b) { return a.stamp_ns < b.stamp_ns; });
    if (unsorted != body.samples.end())
      throw InputError("recorded trajectory", Str("body '", body.name, "': samples not in time order (sample ",
                                                  unsorted - body.samples.begin(), ")"));
    if (!body.samples.empty()) last_stamp_ns_ = std::max(last_stamp_ns_, body.samples.back().stamp_ns);
  }
}

BodyState RecordedTrajectory::At(int body_index, double t_s) const {
  const std::vector<PoseSample>& samples = bodies_.at(static_cast<size_t>(body_index)).samples;
  const int64_t stamp_ns = options_.origin_ns + std::llround(t_s * 1e9);
  BodyState state;
  state.forced_missing = true;
  if (samples.empty() || stamp_ns < samples.front().stamp_ns || stamp_ns > samples.back().stamp_ns) return state;
  const PoseSample& nearest = Nearest(samples, stamp_ns);
  const InterpolatedPose interpolated = InterpolatePose(samples, stamp_ns, options_.interpolation);
  if (interpolated.ok()) {
    state.T_tracker_body = *interpolated.pose;
    state.forced_missing = false;
  } else if (interpolated.failure == InterpolationFailure::kNeighbourInvalid && ReportsPose(nearest.status) &&
             std::abs(nearest.stamp_ns - stamp_ns) <= options_.hold_ns) {
    state.T_tracker_body = nearest.pose;
    state.forced_missing = false;
  }
  if (!state.forced_missing) state.port_status_bits = VolumeBits(nearest.status);
  return state;
}

}  // namespace mocap::ndi
