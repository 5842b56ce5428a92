#include "calibrate/tag_marker_pose.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "calibrate/cv_convert.h"
#include "calibrate/robust_stats.h"
#include "core/check.h"

namespace mocap {
namespace {

constexpr size_t kMaxMarkedTags = 6;

struct MarkerPlane {
  Eigen::Vector3d centroid, normal, axis;  // axis: the direction of largest spread
};

MarkerPlane FitMarkerPlane(const std::vector<Eigen::Vector3d>& points) {
  const PrincipalAxes principal = PrincipalAxesOf(points);
  return {principal.centroid, principal.axes.col(0), principal.axes.col(2)};
}

std::optional<MarkedTag> TagAround(const std::vector<Eigen::Vector3d>& m, size_t i, const MarkerPlane& plane, double tol) {
  std::vector<size_t> order(m.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return (m[a] - m[i]).norm() < (m[b] - m[i]).norm(); });
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (size_t k = 1; k <= 4; ++k) mean += m[order[k]] / 4;
  if ((mean - m[i]).norm() > tol || (m[order[4]] - m[i]).norm() - (m[order[1]] - m[i]).norm() > tol) return std::nullopt;
  MarkedTag tag{i, {order[1], order[2], order[3], order[4]}};
  const Eigen::Vector3d side = plane.normal.cross(plane.axis);
  const auto angle = [&](size_t k) { return std::atan2((m[k] - m[i]).dot(side), (m[k] - m[i]).dot(plane.axis)); };
  std::sort(tag.corners.begin(), tag.corners.end(), [&](size_t a, size_t b) { return angle(a) < angle(b); });
  return tag;
}

struct Hypothesis {
  std::vector<size_t> group_of_tag;  // detected tag t lies on marked tag group_of_tag[t]
  size_t shift = 0;                  // detected corner k is marker corner (shift +- k) mod 4
  bool reversed = false;
  Rigid3d T_camera_world;
  double rms_px = 0;
};

size_t MarkerCorner(const Hypothesis& h, size_t k) { return h.reversed ? (h.shift + 4 - k) % 4 : (h.shift + k) % 4; }

void Correspondences(const Hypothesis& h, const std::vector<TagDetection>& tags, const std::vector<MarkedTag>& groups,
                     const std::vector<Eigen::Vector3d>& m, std::vector<cv::Point3d>& object, std::vector<cv::Point2d>& image) {
  for (size_t t = 0; t < tags.size(); ++t)
    for (size_t k = 0; k < 4; ++k) {
      const Eigen::Vector3d& p = m[groups[h.group_of_tag[t]].corners[MarkerCorner(h, k)]];
      object.emplace_back(p.x(), p.y(), p.z());
      image.emplace_back(tags[t].corners_px[k].x(), tags[t].corners_px[k].y());
    }
}

bool Solve(const std::vector<TagDetection>& tags, const std::vector<MarkedTag>& groups,
           const std::vector<Eigen::Vector3d>& m, const PinholeCamera& camera, Hypothesis& h) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  Correspondences(h, tags, groups, m, object, image);
  const cv::Mat K = CvCameraMatrix(camera), dist = CvDistCoeffs(camera);
  cv::Mat rvec, tvec;
  try {
    if (!cv::solvePnP(object, image, K, dist, rvec, tvec, false, cv::SOLVEPNP_SQPNP)) return false;
    cv::solvePnPRefineLM(object, image, K, dist, rvec, tvec);
  } catch (const cv::Exception&) {
    return false;
  }
  h.T_camera_world = RigidFromCv(cv::Vec3d(rvec), cv::Vec3d(tvec));
  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, rvec, tvec, K, dist, projected);
  double sum = 0;
  for (size_t i = 0; i < image.size(); ++i) sum += std::pow(cv::norm(image[i] - projected[i]), 2);
  h.rms_px = std::sqrt(sum / static_cast<double>(image.size()));
  return true;
}

std::vector<Hypothesis> AllHypotheses(const std::vector<TagDetection>& tags, const std::vector<MarkedTag>& groups,
                                      const std::vector<Eigen::Vector3d>& m, const PinholeCamera& camera) {
  std::vector<size_t> order(groups.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::vector<Hypothesis> all;
  do {
    for (size_t shift = 0; shift < 4; ++shift)
      for (const bool reversed : {false, true}) {
        Hypothesis h{{order.begin(), order.begin() + static_cast<long>(tags.size())}, shift, reversed, {}, 0};
        if (Solve(tags, groups, m, camera, h)) all.push_back(std::move(h));
      }
  } while (std::next_permutation(order.begin(), order.end()));
  std::sort(all.begin(), all.end(), [](const Hypothesis& a, const Hypothesis& b) { return a.rms_px < b.rms_px; });
  return all;
}

bool Admissible(const Hypothesis& h, const MarkerPlane& plane, const TagMarkerOptions& options) {
  const Rigid3d T_world_camera = h.T_camera_world.inverse();
  // The image's y axis points down: seen upright, it has a negative component along the world's up.
  if (options.world_up.norm() > 0 && T_world_camera.rotation_matrix().col(1).dot(options.world_up) >= 0) return false;
  if (!options.camera_near_world) return true;
  const double near_side = (*options.camera_near_world - plane.centroid).dot(plane.normal);
  return near_side * (T_world_camera.translation() - plane.centroid).dot(plane.normal) > 0;
}

// Centre markers vs the crossing of each tag's diagonals (undistorted, so the crossing is the centre's image).
double CentreRmsPx(const Hypothesis& h, const std::vector<TagDetection>& tags, const std::vector<MarkedTag>& groups,
                   const std::vector<Eigen::Vector3d>& m, const PinholeCamera& camera) {
  double sum = 0;
  for (size_t t = 0; t < tags.size(); ++t) {
    std::array<Eigen::Vector3d, 4> ray;
    for (size_t k = 0; k < 4; ++k) ray[k] = camera.Ray(tags[t].corners_px[k]);
    const Eigen::Vector3d crossing = ray[0].cross(ray[2]).cross(ray[1].cross(ray[3]));
    const auto image = camera.Project(crossing / crossing.z());
    const auto marker = camera.Project(h.T_camera_world * m[groups[h.group_of_tag[t]].centre]);
    sum += image && marker ? (*image - *marker).squaredNorm() : 1e12;
  }
  return std::sqrt(sum / static_cast<double>(tags.size()));
}

std::vector<MarkedTag> CheckedGroups(const std::vector<TagDetection>& tags, const std::vector<Eigen::Vector3d>& markers_world,
                                     const TagMarkerOptions& options) {
  const std::vector<MarkedTag> groups = GroupTagMarkers(markers_world, options.group_tolerance_m);
  const std::string where = "LocateCameraByTagMarkers";
  if (groups.empty())
    throw InputError(where, Str("no tag found among ", markers_world.size(), " markers: each tag needs a marker on "
                                "its centre and one on each outer corner"));
  if (groups.size() > kMaxMarkedTags) throw InputError(where, Str(groups.size(), " marked tags (at most 6)"));
  if (tags.empty() || tags.size() > groups.size())
    throw InputError(where, Str(tags.size(), " tags detected in the image but ", groups.size(), " marked"));
  return groups;
}

TagMarkerPose ResultOf(const Hypothesis& h, const std::vector<TagDetection>& tags, const std::vector<MarkedTag>& groups,
                       const std::vector<Eigen::Vector3d>& m, const PinholeCamera& camera) {
  TagMarkerPose result;
  result.T_world_camera = h.T_camera_world.inverse();
  result.rms_px = h.rms_px;
  result.tags_used = tags.size();
  result.corners_used = 4 * tags.size();
  result.tag_id_of_group.assign(groups.size(), -1);
  for (size_t t = 0; t < tags.size(); ++t) result.tag_id_of_group[h.group_of_tag[t]] = tags[t].id;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  Correspondences(h, tags, groups, m, object, image);
  for (size_t i = 0; i < object.size(); ++i) {
    const auto projected = camera.Project(h.T_camera_world * Eigen::Vector3d(object[i].x, object[i].y, object[i].z));
    result.residuals_px.push_back(Eigen::Vector2d(image[i].x, image[i].y) - projected.value_or(Eigen::Vector2d(-1e6, -1e6)));
  }
  result.centre_rms_px = CentreRmsPx(h, tags, groups, m, camera);
  return result;
}

}  // namespace

std::vector<MarkedTag> GroupTagMarkers(const std::vector<Eigen::Vector3d>& markers_world, double tolerance_m) {
  std::vector<MarkedTag> groups;
  if (markers_world.size() < 5) return groups;
  const MarkerPlane plane = FitMarkerPlane(markers_world);
  std::vector<bool> used(markers_world.size(), false);
  for (size_t i = 0; i < markers_world.size(); ++i) {
    const std::optional<MarkedTag> tag = TagAround(markers_world, i, plane, tolerance_m);
    if (!tag || used[i] || std::any_of(tag->corners.begin(), tag->corners.end(), [&](size_t c) { return used[c]; }))
      continue;
    used[i] = true;
    for (const size_t c : tag->corners) used[c] = true;
    groups.push_back(*tag);
  }
  return groups;
}

TagMarkerPose LocateCameraByTagMarkers(const std::vector<TagDetection>& tags,
                                       const std::vector<Eigen::Vector3d>& markers_world,
                                       const PinholeCamera& camera, const TagMarkerOptions& options) {
  camera.check();
  const std::vector<MarkedTag> groups = CheckedGroups(tags, markers_world, options);
  const std::vector<Hypothesis> all = AllHypotheses(tags, groups, markers_world, camera);
  const MarkerPlane plane = FitMarkerPlane(markers_world);
  const auto chosen = std::find_if(all.begin(), all.end(), [&](const Hypothesis& h) { return Admissible(h, plane, options); });
  if (chosen == all.end())
    throw InputError("LocateCameraByTagMarkers", "no camera pose is upright and in front of the tags");
  TagMarkerPose result = ResultOf(*chosen, tags, groups, markers_world, camera);
  const double band = options.lookalike_factor * all.front().rms_px + 1.0;
  for (const Hypothesis& h : all) {
    if (&h == &*chosen || h.rms_px > band) continue;
    if (result.lookalikes++ == 0) {
      result.rejected_best_rms_px = h.rms_px;
      result.rejected_camera_shift_m = TranslationDistanceM(h.T_camera_world.inverse(), result.T_world_camera);
    }
  }
  if (chosen->rms_px > band)
    result.warnings.push_back(Str("the chosen pose fits at ", chosen->rms_px, " px but a rejected one at ",
                                  all.front().rms_px, " px: check world_up and camera_near_world"));
  return result;
}

MarkerCentroidRelativePose RelativeToMarkerCentroid(const Rigid3d& T_world_camera,
                                                    const std::vector<Eigen::Vector3d>& body_markers_world) {
  MOCAP_CHECK(!body_markers_world.empty(), "no body markers");
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : body_markers_world) mean += p / static_cast<double>(body_markers_world.size());
  return {T_world_camera.translation() - mean, T_world_camera.rotation_matrix()};
}

}  // namespace mocap
