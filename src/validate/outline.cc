#include "validate/outline.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <vector>

#include "core/check.h"
#include "validate/frame_visibility.h"
#include "validate/point_grid.h"

namespace mocap {

void OutlineOptions::check() const {
  if (!(search_m > 0 && search_m <= 0.2)) throw InputError("OutlineOptions", "search_m must lie in (0, 0.2]");
  if (!(step_m > 0 && step_m <= search_m)) throw InputError("OutlineOptions", "step_m must lie in (0, search_m]");
  if (!(surface_gate_m > 0)) throw InputError("OutlineOptions", "surface_gate_m must be positive");
  if (!(min_rise >= 0 && min_rise < 1)) throw InputError("OutlineOptions", "min_rise must lie in [0, 1)");
  if (max_pixels < 100) throw InputError("OutlineOptions", "max_pixels must be >= 100");
}

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

/// The pixel of a camera-frame point, or nullopt (behind the camera or outside the image).
std::optional<Eigen::Vector2i> PixelOf(const PinholeCamera& camera, const Eigen::Vector3d& p_camera, const DepthImage& image) {
  if (!(p_camera.z() > 0)) return std::nullopt;
  const auto pixel = NearestPixelOf(camera, !camera.has_distortion(), p_camera);
  if (!pixel || !image.contains(pixel->x(), pixel->y())) return std::nullopt;
  return pixel;
}

/// The pixels within about `radius_px` of the label mask's outline, on either side, over the box of the
/// mask grown by the radius (a mask running off the image has no outline there). Counted on cells of 2 x 2
/// pixels (each by its first pixel): the band only chooses what the cost looks at, and a table's mask
/// covers most of the image.
class OutlineBand {
 public:
  OutlineBand(const LabelImage& label, uint16_t id, int radius_px)
      : cols_((label.width + 1) / 2), rows_((label.height + 1) / 2), r_((radius_px + 1) / 2), width_(label.width),
        height_(label.height) {
    int hi_x = -1, hi_y = -1;
    lo_x_ = cols_, lo_y_ = rows_;
    for (int y = 0; y < rows_; ++y)
      for (int x = 0; x < cols_; ++x)
        if (label.at(2 * x, 2 * y) == id) lo_x_ = std::min(lo_x_, x), hi_x = std::max(hi_x, x), lo_y_ = std::min(lo_y_, y), hi_y = std::max(hi_y, y);
    if (hi_x < 0) return;
    lo_x_ = std::max(0, lo_x_ - r_), lo_y_ = std::max(0, lo_y_ - r_);
    w_ = std::min(cols_ - 1, hi_x + r_) - lo_x_ + 1, h_ = std::min(rows_ - 1, hi_y + r_) - lo_y_ + 1;
    sum_.assign(static_cast<size_t>(w_ + 1) * (h_ + 1), 0);
    for (int y = 0; y < h_; ++y)
      for (int x = 0; x < w_; ++x)
        At(x + 1, y + 1) = At(x, y + 1) + At(x + 1, y) - At(x, y) + (label.at(2 * (lo_x_ + x), 2 * (lo_y_ + y)) == id);
  }
  bool InBox(int u, int v) const {
    const int x = u / 2 - lo_x_, y = v / 2 - lo_y_;
    return u >= 0 && v >= 0 && x >= 0 && y >= 0 && x < w_ && y < h_;
  }
  /// Whether pixel (u, v)'s window holds both label and other cells. Windows are clipped to the image,
  /// not to the box (the box holds every label cell).
  bool Near(int u, int v) const {
    if (!InBox(u, v)) return false;
    const int cx = u / 2, cy = v / 2, x = cx - lo_x_, y = cy - lo_y_;
    const int x0 = std::max(0, x - r_), x1 = std::min(w_, x + r_ + 1), y0 = std::max(0, y - r_), y1 = std::min(h_, y + r_ + 1);
    const int count = At(x1, y1) - At(x0, y1) - At(x1, y0) + At(x0, y0);
    const int full = (std::min(cols_, cx + r_ + 1) - std::max(0, cx - r_)) * (std::min(rows_, cy + r_ + 1) - std::max(0, cy - r_));
    return count > 0 && count < full;
  }
  int64_t label_pixels() const { return sum_.empty() ? 0 : 4 * static_cast<int64_t>(At(w_, h_)); }
  /// The box in pixels.
  int lo_u() const { return 2 * lo_x_; }
  int lo_v() const { return 2 * lo_y_; }
  int width() const { return std::min(width_, 2 * (lo_x_ + w_)) - lo_u(); }
  int height() const { return std::min(height_, 2 * (lo_y_ + h_)) - lo_v(); }
  int radius_px() const { return 2 * r_; }

 private:
  int& At(int x, int y) { return sum_[static_cast<size_t>(y) * (w_ + 1) + x]; }
  int At(int x, int y) const { return sum_[static_cast<size_t>(y) * (w_ + 1) + x]; }
  int cols_, rows_, r_, width_, height_;     // the image in cells, the radius in cells; the image in pixels
  int lo_x_ = 0, lo_y_ = 0, w_ = 0, h_ = 0;  // the box, in cells
  std::vector<int> sum_;
};

/// The outline's disagreement at a pose, in crop points: model over no measured surface, and measured
/// surface outside the model's silhouette. Made once at the estimate; only what lies near the outline
/// takes part (deep inside, a small move changes nothing).
class OutlineCost {
 public:
  OutlineCost(const OutlineFrame& f, const OutlineOptions& options, const ObservabilityOptions& observability,
              const Rigid3d& T_camera_object)
      : f_(f), gate_m_(options.surface_gate_m) {
    const PointCloud crop = f.model->CropPoints(T_camera_object).points_model;
    const size_t stride = std::max<size_t>(1, (crop.size() + static_cast<size_t>(observability.max_points) - 1) /
                                                  static_cast<size_t>(observability.max_points));
    crop_weight_ = static_cast<double>(stride);
    PointCloud sampled, sampled_camera;
    for (size_t i = 0; i < crop.size(); i += stride) sampled.push_back(crop[i]), sampled_camera.push_back(T_camera_object * crop[i]);
    int seen = 0;
    Unsupported(sampled, T_camera_object, &seen);
    visible_points_ = crop_weight_ * seen;
    if (seen == 0) return;
    // The band reaches as far as the search moves the outline, at the object's range.
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : sampled_camera) centroid += p;
    const double z_m = std::max(0.1, centroid.z() / static_cast<double>(sampled_camera.size()));
    const OutlineBand band(*f.label_mask, f.label_id, static_cast<int>(std::ceil(options.search_m * f.camera->fx / z_m)) + 2);
    KeepNearOutline(sampled, T_camera_object, band);
    SampleSurfacePixels(band, PointGrid(sampled_camera, PointGridOptions{options.surface_gate_m}), options.max_pixels);
  }

  /// Crop points (of the whole crop) the frame sees at the estimate.
  double visible_points() const { return visible_points_; }

  double operator()(const Rigid3d& T_camera_object) const {
    return OverNothing(T_camera_object) + pixel_weight_ * Unexplained(T_camera_object);
  }

  /// The first part alone: the model over no measured surface. It reads neither the label pose nor its mask.
  double OverNothing(const Rigid3d& T_camera_object) const {
    int seen = 0;
    return crop_weight_ * Unsupported(crop_, T_camera_object, &seen);
  }

 private:
  /// The crop points near the outline at T, or outside the image (they may come into it).
  void KeepNearOutline(const PointCloud& sampled, const Rigid3d& T, const OutlineBand& band) {
    for (const Eigen::Vector3d& p : sampled) {
      const auto pixel = PixelOf(*f_.camera, T * p, *f_.depth_m);
      if (!pixel || band.Near(pixel->x(), pixel->y()) || !band.InBox(pixel->x(), pixel->y())) crop_.push_back(p);
    }
  }

  /// The band's pixels with measured depth on the object's surface (within the gate of the crop at the
  /// estimate: the floor beyond a table's edge is not the table's whatever the pose), not another
  /// object's; every q-th in both directions (q keeping about max_pixels), each standing for q^2 pixels
  /// and for the crop points a label pixel holds.
  void SampleSurfacePixels(const OutlineBand& band, const PointGrid& crop_camera, int max_pixels) {
    // The band covers about the outline's length times twice the radius; the box's perimeter bounds it.
    const double band_px = 2.0 * (band.width() + band.height()) * 2.0 * band.radius_px();
    const int q = std::max(1, static_cast<int>(std::ceil(std::sqrt(band_px / max_pixels))));
    for (int v = band.lo_v(); v < band.lo_v() + band.height(); v += q)
      for (int u = band.lo_u(); u < band.lo_u() + band.width(); u += q) {
        const uint16_t owner = f_.mask->at(u, v);
        const float z_m = f_.depth_m->at(u, v);
        if (!(z_m > 0) || (owner != 0 && owner != f_.label_id) || !band.Near(u, v)) continue;
        const Eigen::Vector3d x = f_.camera->Unproject(Eigen::Vector2d(u, v), z_m);
        if (crop_camera.AnyWithin(x, gate_m_)) surface_.push_back(x);
      }
    const int64_t label_pixels = band.label_pixels();
    pixel_weight_ = label_pixels > 0 ? static_cast<double>(q) * q * visible_points_ / static_cast<double>(label_pixels) : 0.0;
  }

  /// Of `crop` at T, the points over no measured surface; `seen` receives those the frame can see (as
  /// VisibleInFrameCropSource: not outside the image, not hidden by something nearer, not on another
  /// object's pixel without depth).
  int Unsupported(const PointCloud& crop, const Rigid3d& T, int* seen) const {
    const Eigen::Matrix3d R = T.rotation_matrix();
    const Eigen::Vector3d t = T.translation();
    int unsupported = 0;
    *seen = 0;
    for (const Eigen::Vector3d& p_model : crop) {
      const Eigen::Vector3d p = R * p_model + t;
      const auto pixel = PixelOf(*f_.camera, p, *f_.depth_m);
      if (!pixel) continue;
      const float measured_m = f_.depth_m->at(pixel->x(), pixel->y());
      const uint16_t owner = f_.mask->at(pixel->x(), pixel->y());
      // Another object's pixel without depth hides what lies behind it; the label's own pixels without
      // depth do not count as the object's (a label overhanging the table's edge covers the depthless
      // background beyond it).
      if (owner != 0 && owner != f_.label_id && !(measured_m > 0)) continue;
      if (owner != f_.label_id && measured_m > 0 && measured_m < p.z() - f_.occluder_margin_m) continue;
      ++*seen;
      unsupported += !(measured_m > 0 && std::abs(measured_m - p.z()) < gate_m_);
    }
    return unsupported;
  }

  /// Measured surface points outside the model's silhouette at T: each, carried by the motion from T to
  /// the label pose, lands outside the label's rendered mask (on another object's pixel: no evidence).
  int Unexplained(const Rigid3d& T) const {
    const Rigid3d T_label_from_pose = f_.T_camera_object_label * T.inverse();
    int unexplained = 0;
    for (const Eigen::Vector3d& x : surface_) {
      const auto pixel = PixelOf(*f_.camera, T_label_from_pose * x, *f_.depth_m);
      if (pixel) unexplained += f_.label_mask->at(pixel->x(), pixel->y()) == 0;
    }
    return unexplained;
  }

  const OutlineFrame& f_;
  double gate_m_;
  PointCloud crop_;               ///< sampled crop points near the outline (object frame)
  double crop_weight_ = 1.0;      ///< crop points each stands for
  double visible_points_ = 0.0;
  PointCloud surface_;            ///< band pixels on the object's surface (camera frame)
  double pixel_weight_ = 0.0;     ///< crop points each stands for
};

/// The cost along one direction: sampled every 2 step_m over +-search_m, then at step_m beside the
/// lowest; its minimum and the rise probe_m either side of it.
class LineSearch {
 public:
  LineSearch(const std::function<double(double)>& cost, double step_m, double search_m) : step_m_(step_m), search_m_(search_m) {
    const int n = static_cast<int>(std::lround(search_m / step_m));
    for (int i = -n; i <= n; i += 2) Add(i, cost);
    const int coarse = Lowest();
    if (coarse - 1 >= -n) Add(coarse - 1, cost);
    if (coarse + 1 <= n) Add(coarse + 1, cost);
  }
  /// The minimum: the lowest sample (nearest the middle among ties), moved by the V through it and its
  /// neighbours.
  double Minimum() const {
    const int i = Lowest();
    double s = step_m_ * i;
    const auto left = values_.find(i - 1), right = values_.find(i + 1);
    if (left != values_.end() && right != values_.end()) {
      const double middle = values_.at(i), steeper = std::max(left->second, right->second) - middle;
      if (steeper > 0) s += 0.5 * step_m_ * (left->second - right->second) / steeper;
    }
    return s;
  }
  /// The cost at s, linear between samples (clamped to the ends).
  double At(double s) const {
    const double x = std::clamp(s, -search_m_, search_m_) / step_m_;
    auto hi = values_.lower_bound(static_cast<int>(std::ceil(x)));
    if (hi == values_.end()) return std::prev(hi)->second;
    if (hi == values_.begin() || hi->first == x) return hi->second;
    const auto lo = std::prev(hi);
    return lo->second + (x - lo->first) / (hi->first - lo->first) * (hi->second - lo->second);
  }

 private:
  void Add(int i, const std::function<double(double)>& cost) { values_.emplace(i, cost(step_m_ * i)); }
  int Lowest() const {
    int best = values_.begin()->first;
    for (const auto& [i, v] : values_)
      if (v < values_.at(best) || (v == values_.at(best) && std::abs(i) < std::abs(best))) best = i;
    return best;
  }
  double step_m_, search_m_;
  std::map<int, double> values_;  // sample index (s / step_m) -> cost
};

/// The line search of `cost` along `d` (analysis coordinates) from *T: the step, and *T moved to the
/// minimum when the outline bounds the move both ways. `visible`: crop points the frame sees.
OutlineStep SearchAlong(const std::function<double(const Rigid3d&)>& cost, double visible, const Vector6d& d,
                        const OutlineOptions& options, const ObservabilityOptions& observability, const Observability& o,
                        Rigid3d* T) {
  const Rigid3d start = *T;
  const LineSearch line([&](double s) { return cost(MovedAlong(start, s * d, o.center_object, o.radius_m)); },
                        options.step_m, options.search_m);
  OutlineStep step;
  const double s = line.Minimum();
  const double rise = std::min(line.At(s - observability.probe_m), line.At(s + observability.probe_m)) - line.At(s);
  step.rise = visible > 0 ? rise / visible : 0.0;
  step.judged = visible > 0 && rise >= options.min_rise * visible && rise >= observability.probe_min_lost_points;
  if (step.judged) {
    step.shift_m = s;
    *T = MovedAlong(start, s * d, o.center_object, o.radius_m);
  }
  return step;
}

/// The moves across the ray through the analysis centre: along the image's x, then its y. They take the
/// model's side of the cost alone, which reads neither the label pose nor its mask: the estimate these
/// moves make owes nothing to the label it is then compared with (the measured surface's side reads the
/// label run's mask as the model's silhouette).
std::vector<OutlineStep> MoveAcrossRay(const OutlineCost& cost, const Eigen::Vector3d& tof_center_camera,
                                       const OutlineOptions& options, const ObservabilityOptions& observability,
                                       const Observability& o, Rigid3d* T_camera_object) {
  const Eigen::Vector3d ray = (*T_camera_object * o.center_object - tof_center_camera).normalized();
  const Eigen::Vector3d x_camera = Eigen::Vector3d::UnitY().cross(ray).normalized();
  const Eigen::Vector3d across[2] = {x_camera, ray.cross(x_camera)};
  std::vector<OutlineStep> steps;
  for (int i = 0; i < 2; ++i) {
    Vector6d d;
    d << Eigen::Vector3d::Zero(), T_camera_object->rotation().inverse() * across[i];
    OutlineStep step = SearchAlong([&](const Rigid3d& T) { return cost.OverNothing(T); }, cost.visible_points(), d,
                                   options, observability, o, T_camera_object);
    step.direction = i;
    step.across_ray = true;
    steps.push_back(step);
  }
  return steps;
}

}  // namespace

std::vector<OutlineStep> EstimateAlongOutline(const OutlineFrame& frame, const OutlineOptions& options,
                                              const ObservabilityOptions& observability, Rigid3d* T_camera_object,
                                              Observability* o, bool across_ray) {
  std::vector<OutlineStep> steps;
  if (!o->analysed) return steps;
  std::optional<OutlineCost> cost;  // made at the first such direction, at the estimate
  for (int k = 0; k < 6; ++k) {
    if (!(o->information(k) < kMinProbedInformation)) continue;
    const Vector6d d = o->directions.col(k);
    // A turn no normal resists is not judged: a body of revolution's spin, or a table's, which its edges
    // in view bound too weakly (the probe's 3 % of a table's crop is its noise).
    if (d.head<3>().norm() > d.tail<3>().norm()) {
      o->judged[k] = false;
      continue;
    }
    if (!cost) cost.emplace(frame, options, observability, *T_camera_object);
    // The outline, not the probe, judges the slide: judged, the estimate moves to the outline's minimum.
    OutlineStep step = SearchAlong(*cost, cost->visible_points(), d, options, observability, *o, T_camera_object);
    step.direction = k;
    o->judged[k] = step.judged;
    o->probe_loss[k] = step.rise;
    steps.push_back(step);
  }
  SummariseObservability(o);
  if (across_ray) {
    if (!cost) cost.emplace(frame, options, observability, *T_camera_object);
    const std::vector<OutlineStep> across = MoveAcrossRay(*cost, frame.tof_center_camera, options, observability, *o, T_camera_object);
    steps.insert(steps.end(), across.begin(), across.end());
  }
  return steps;
}

}  // namespace mocap
