#pragma once
// Named frames and the transforms between them, fixed (calibration) or time-varying (tracker streams).
// Lookup("camera", "mesh:bottle", t) finds the chain and composes it, e.g.
// T_camera_mesh = inv(T_tracker_cambody * T_cambody_camera) * T_tracker_objbody * T_objbody_mesh.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/pose_stream.h"
#include "core/rigid3.h"

namespace mocap {

struct FrameLookup {
  std::optional<Rigid3d> T_a_b;  ///< set when every edge of the chain gave a transform
  std::vector<std::string> chain;  ///< frames from a to b
  /// When T_a_b is empty: which edge failed and why (no path, or the interpolation's reason).
  std::string reason;
  InterpolationFailure failure = InterpolationFailure::kNone;
  PoseStatus neighbour_status = PoseStatus::kValid;  ///< the offending status for kNeighbourInvalid
  int64_t max_gap_ns = 0;  ///< the longest interpolation gap used along the chain
  bool ok() const { return T_a_b.has_value(); }
};

class FrameGraph {
 public:
  explicit FrameGraph(InterpolationOptions options = {});

  /// A calibration: T_parent_child fixed in time. Throws InputError if the edge exists already.
  void AddFixed(const std::string& parent, const std::string& child, const Rigid3d& T_parent_child);
  /// A tracked body: T_parent_child(t) from samples sorted by stamp (copied).
  void AddStream(const std::string& parent, const std::string& child, std::vector<PoseSample> samples);

  bool HasFrame(const std::string& frame) const;
  /// T_a_b at host time stamp_ns; a and b must be connected (else a reason, no transform).
  FrameLookup Lookup(const std::string& a, const std::string& b, int64_t stamp_ns) const;

 private:
  struct Edge {
    std::string parent, child;
    std::optional<Rigid3d> fixed;
    std::vector<PoseSample> samples;
  };
  void AddEdge(Edge edge);
  std::optional<std::vector<std::pair<const Edge*, bool>>> FindPath(const std::string& a, const std::string& b) const;

  InterpolationOptions options_;
  std::vector<Edge> edges_;
  std::map<std::string, std::vector<size_t>> adjacency_;
};

}  // namespace mocap
