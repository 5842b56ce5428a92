#include "core/frame_graph.h"

#include <algorithm>
#include <deque>

#include "core/check.h"

namespace mocap {

FrameGraph::FrameGraph(InterpolationOptions options) : options_(options) { options_.check(); }

void FrameGraph::AddEdge(Edge edge) {
  if (edge.parent == edge.child) throw InputError("frame graph", Str("frame '", edge.parent, "' linked to itself"));
  for (const Edge& e : edges_) {
    if ((e.parent == edge.parent && e.child == edge.child) || (e.parent == edge.child && e.child == edge.parent))
      throw InputError("frame graph", Str("transform between '", edge.parent, "' and '", edge.child, "' given twice"));
  }
  adjacency_[edge.parent].push_back(edges_.size());
  adjacency_[edge.child].push_back(edges_.size());
  edges_.push_back(std::move(edge));
}

void FrameGraph::AddFixed(const std::string& parent, const std::string& child, const Rigid3d& T_parent_child) {
  AddEdge({parent, child, T_parent_child, {}});
}

void FrameGraph::AddStream(const std::string& parent, const std::string& child, std::vector<PoseSample> samples) {
  MOCAP_CHECK(std::is_sorted(samples.begin(), samples.end(),
                             [](const PoseSample& x, const PoseSample& y) { return x.stamp_ns < y.stamp_ns; }),
              "samples of '", child, "' are not sorted by time");
  AddEdge({parent, child, std::nullopt, std::move(samples)});
}

bool FrameGraph::HasFrame(const std::string& frame) const { return adjacency_.contains(frame); }

// Breadth-first search; each step is an edge and whether it is walked child-to-parent (inverted).
std::optional<std::vector<std::pair<const FrameGraph::Edge*, bool>>> FrameGraph::FindPath(const std::string& a,
                                                                                          const std::string& b) const {
  std::map<std::string, std::pair<std::string, size_t>> came_from;
  std::deque<std::string> queue{a};
  came_from[a] = {a, SIZE_MAX};
  while (!queue.empty() && !came_from.contains(b)) {
    const std::string frame = queue.front();
    queue.pop_front();
    const auto it = adjacency_.find(frame);
    if (it == adjacency_.end()) continue;
    for (size_t e : it->second) {
      const std::string& other = edges_[e].parent == frame ? edges_[e].child : edges_[e].parent;
      if (came_from.contains(other)) continue;
      came_from[other] = {frame, e};
      queue.push_back(other);
    }
  }
  if (!came_from.contains(b)) return std::nullopt;
  std::vector<std::pair<const Edge*, bool>> path;
  for (std::string f = b; f != a; f = came_from[f].first) {
    const Edge& edge = edges_[came_from[f].second];
    // Walking from a towards b we arrive at f; the step maps f into its predecessor.
    path.emplace_back(&edge, edge.parent == f);
  }
  std::reverse(path.begin(), path.end());
  return path;
}

FrameLookup FrameGraph::Lookup(const std::string& a, const std::string& b, int64_t stamp_ns) const {
  FrameLookup out;
  if (a == b) {
    out.T_a_b = Rigid3d::Identity();
    out.chain = {a};
    return out;
  }
  const auto path = FindPath(a, b);
  if (!path) {
    out.reason = Str("no chain of transforms links '", a, "' and '", b, "'");
    return out;
  }
  Rigid3d T = Rigid3d::Identity();
  out.chain.push_back(a);
  for (const auto& [edge, inverted] : *path) {
    out.chain.push_back(inverted ? edge->parent : edge->child);
    Rigid3d T_parent_child;
    if (edge->fixed) {
      T_parent_child = *edge->fixed;
    } else {
      const InterpolatedPose ip = InterpolatePose(edge->samples, stamp_ns, options_);
      if (!ip.ok()) {
        out.failure = ip.failure;
        out.neighbour_status = ip.neighbour_status;
        out.reason = Str("'", edge->child, "' in '", edge->parent, "': ", ip.reason());
        return out;
      }
      out.max_gap_ns = std::max(out.max_gap_ns, ip.gap_ns);
      T_parent_child = *ip.pose;
    }
    T = T * (inverted ? T_parent_child.inverse() : T_parent_child);
  }
  out.T_a_b = T;
  return out;
}

}  // namespace mocap
