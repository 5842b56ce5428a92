#include "validate/depth_time.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "core/check.h"

namespace mocap {

void DepthTimeOptions::check() const {
  if (max_label_gap_ns <= 0) throw InputError("validate.depth_time.max_label_gap_ns", "must be positive");
}

namespace {

/// The records of one instance in one camera, by colour stamp.
using InstanceTrack = std::vector<size_t>;

std::map<std::pair<std::string, int>, InstanceTrack> TracksOf(const std::vector<RecordCheck>& records) {
  std::map<std::pair<std::string, int>, InstanceTrack> tracks;
  for (size_t i = 0; i < records.size(); ++i) tracks[{records[i].camera, records[i].instance}].push_back(i);
  for (auto& [key, track] : tracks)
    std::ranges::sort(track, [&](size_t a, size_t b) { return records[a].stamp_ns < records[b].stamp_ns; });
  return tracks;
}

}  // namespace

DepthTimeMoves MoveLabelsToDepthTime(const SessionReader& session, std::vector<RecordCheck>& records,
                                     const DepthTimeOptions& options) {
  options.check();
  DepthTimeMoves moves;
  std::vector<Rigid3d> moved(records.size());
  std::vector<int64_t> shift_ns(records.size(), 0);
  for (RecordCheck& r : records) {
    // A record naming no frame of the session is left as it is: the session check reports it by name.
    if (!session.manifest().FindCamera(r.camera) || r.index < 0 || r.index >= session.frame_count(r.camera)) continue;
    const CameraFrameRecord& frame = session.frame(r.camera, r.index).record;
    r.depth_offset_ns = frame.depth_time_ns() - frame.stamp_ns;
  }
  for (const auto& [key, track] : TracksOf(records)) {
    for (size_t k = 0; k < track.size(); ++k) {
      const RecordCheck& r = records[track[k]];
      if (r.depth_offset_ns == 0) continue;
      const int64_t depth_ns = r.stamp_ns + r.depth_offset_ns;
      // The neighbour on the depth's side of the colour exposure brackets the depth's time with it.
      const bool before = depth_ns < r.stamp_ns;
      const bool has_neighbour = before ? k > 0 : k + 1 < track.size();
      const RecordCheck* other = has_neighbour ? &records[track[before ? k - 1 : k + 1]] : nullptr;
      const int64_t gap_ns = other ? std::abs(r.stamp_ns - other->stamp_ns) : 0;
      if (!other || gap_ns == 0 || gap_ns > options.max_label_gap_ns || std::abs(depth_ns - r.stamp_ns) > gap_ns) {
        ++moves.unmovable;
        continue;
      }
      const double alpha = static_cast<double>(std::abs(depth_ns - r.stamp_ns)) / static_cast<double>(gap_ns);
      moved[track[k]] = Interpolate(r.T_camera_object_label, other->T_camera_object_label, alpha);
      shift_ns[track[k]] = depth_ns - r.stamp_ns;
      ++moves.moved;
    }
  }
  // Written after every interpolation, so each reads the labels as labelled.
  for (size_t i = 0; i < records.size(); ++i) {
    if (shift_ns[i] == 0) continue;
    records[i].T_camera_object_as_labelled = records[i].T_camera_object_label;
    records[i].T_camera_object_label = moved[i];
    records[i].label_shift_ns = shift_ns[i];
  }
  return moves;
}

}  // namespace mocap
