#include "validate/point_grid.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/check.h"

namespace mocap {
namespace {

constexpr uint8_t kFarRing = 255;
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
/// Edge of the blocks of the empty-ring transform, in cells.
constexpr int kBlockCells = 2;
/// Lower bounds lose this much (in cells) to the float rounding of the points' cell assignment.
constexpr float kSlackCells = 1e-4f;
/// Cell coordinates beyond this magnitude (a query kilometres from a centimetre grid) would overflow
/// the integer cell index; such queries scan every point instead.
constexpr float kMaxCellCoordinate = 1e6f;

/// floor() of a cell coordinate without the libm call (x86-64 without SSE4.1 does not inline floorf,
/// and a query floors up to nine of them). Scalar and inline: the compiler kept Eigen's integer
/// array expressions of three coefficients as calls. Precondition: |x| < 2^31.
inline int FloorCell(float x) {
  const int truncated = static_cast<int>(x);
  return truncated - (x < static_cast<float>(truncated) ? 1 : 0);
}

inline Eigen::Vector3i FloorCells(const Eigen::Vector3f& x) {
  return Eigen::Vector3i(FloorCell(x.x()), FloorCell(x.y()), FloorCell(x.z()));
}

/// The cells of the box g +- reach (in cells), clipped to [lo_bound, hi_bound].
inline void BoxCells(const Eigen::Vector3f& g, float reach, const Eigen::Vector3i& lo_bound,
                     const Eigen::Vector3i& hi_bound, Eigen::Vector3i* lo, Eigen::Vector3i* hi) {
  for (int a = 0; a < 3; ++a) {
    (*lo)[a] = std::max(lo_bound[a], FloorCell(g[a] - reach));
    (*hi)[a] = std::min(hi_bound[a], FloorCell(g[a] + reach));
  }
}

/// Offers point `index` at `d_sq` to a search's answer: it becomes the nearest or may be the second.
inline void Consider(float d_sq, uint32_t index, PointGrid::Best* b) {
  if (d_sq < b->sq) {
    if (b->index != kNone) b->second_sq = std::min(b->second_sq, b->sq);
    b->sq = d_sq;
    b->index = index;
  } else if (d_sq < b->second_sq && index != b->index) {
    b->second_sq = d_sq;
  }
}

/// The 13 neighbours of a cell that precede it in raster order (z, then y, then x).
std::array<Eigen::Vector3i, 13> PrecedingNeighbours() {
  std::array<Eigen::Vector3i, 13> out;
  int k = 0;
  for (int dz = -1; dz <= 0; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (dz < 0 || dy < 0 || (dy == 0 && dx < 0)) out[k++] = Eigen::Vector3i(dx, dy, dz);
  return out;
}

/// One raster pass of the chessboard distance transform over a grid padded by one far cell on every
/// side: each interior cell takes one more than its smallest neighbour among `offsets` (linear; the
/// preceding neighbours when `forward`, else the following ones, negated).
void ChamferPass(const Eigen::Vector3i& padded, const std::array<std::ptrdiff_t, 13>& offsets, bool forward,
                 std::vector<uint8_t>* rings) {
  const std::ptrdiff_t nx = padded.x(), ny = padded.y(), nz = padded.z(), sign = forward ? 1 : -1;
  for (std::ptrdiff_t zi = 1; zi < nz - 1; ++zi)
    for (std::ptrdiff_t yi = 1; yi < ny - 1; ++yi) {
      const std::ptrdiff_t z = forward ? zi : nz - 1 - zi, y = forward ? yi : ny - 1 - yi;
      uint8_t* cell = rings->data() + (z * ny + y) * nx + (forward ? 1 : nx - 2);
      for (std::ptrdiff_t xi = 1; xi < nx - 1; ++xi, cell += sign) {
        int nearest = *cell - 1;
        for (const std::ptrdiff_t o : offsets) nearest = std::min<int>(nearest, cell[sign * o]);
        *cell = static_cast<uint8_t>(std::min<int>(kFarRing, nearest + 1));
      }
    }
}

}  // namespace

void PointGridOptions::check() const {
  if (!(cell_m > 0)) throw InputError("PointGridOptions", "cell_m must be positive");
  if (!(max_cells_per_point > 0)) throw InputError("PointGridOptions", "max_cells_per_point must be positive");
}

PointGrid::PointGrid(const PointCloud& points, const PointGridOptions& options) {
  options.check();
  static std::atomic<uint64_t> next_id{1};
  id_ = next_id.fetch_add(1, std::memory_order_relaxed);
  if (points.empty()) return;
  std::vector<Eigen::Vector3f> input(points.size());
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max()), hi = -lo;
  for (size_t i = 0; i < points.size(); ++i) {
    input[i] = points[i].cast<float>();
    lo = lo.cwiseMin(input[i]);
    hi = hi.cwiseMax(input[i]);
  }
  const Eigen::Vector3d extent_m = (hi - lo).cast<double>();
  const double budget = options.max_cells_per_point * static_cast<double>(points.size()) + 4096.0;
  double cell_m = options.cell_m;
  const auto cells_for = [&](double c) { return ((extent_m / c).array().floor() + 1.0).prod(); };
  while (cells_for(cell_m) > budget) cell_m *= 1.25;
  cell_m_ = static_cast<float>(cell_m);
  inv_cell_ = 1.0f / cell_m_;
  origin_ = lo;
  dims_ = ((extent_m / cell_m).array().floor() + 1.0).cast<int>();
  // Counting sort of the points by cell, stable in input order.
  std::vector<uint32_t> cell_of(input.size());
  cell_start_.assign(static_cast<size_t>(dims_.prod()) + 1, 0);
  for (size_t i = 0; i < input.size(); ++i) {
    const Eigen::Vector3i c =
        ((input[i] - origin_) * inv_cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1);
    cell_of[i] = static_cast<uint32_t>(CellIndex(c.x(), c.y(), c.z()));
    ++cell_start_[cell_of[i] + 1];
  }
  for (size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  std::vector<uint32_t> next(cell_start_.begin(), cell_start_.end() - 1);
  points_.resize(input.size());
  for (size_t i = 0; i < input.size(); ++i) points_[next[cell_of[i]]++] = input[i];
  ComputeEmptyRings();
}

void PointGrid::ComputeEmptyRings() {
  // Over blocks of kBlockCells^3 cells (a transform over the cells themselves costs as much as the
  // queries of a tracking step), padded by one far block on each side so that the passes need no
  // bounds checks.
  block_dims_ = (dims_.array() + kBlockCells - 1) / kBlockCells;
  const Eigen::Vector3i padded = block_dims_.array() + 2;
  empty_rings_.assign(static_cast<size_t>(padded.prod()), kFarRing);
  for (int z = 0; z < dims_.z(); ++z)
    for (int y = 0; y < dims_.y(); ++y)
      for (int x = 0; x < dims_.x(); ++x) {
        const size_t c = CellIndex(x, y, z);
        if (cell_start_[c + 1] > cell_start_[c]) empty_rings_[PaddedBlock(x, y, z)] = 0;
      }
  // Two raster passes over the 26-neighbourhood give the exact chessboard distance (Borgefors 1986).
  std::array<std::ptrdiff_t, 13> offsets{};
  const auto neighbours = PrecedingNeighbours();
  for (size_t k = 0; k < offsets.size(); ++k)
    offsets[k] = (static_cast<std::ptrdiff_t>(neighbours[k].z()) * padded.y() + neighbours[k].y()) * padded.x() +
                 neighbours[k].x();
  ChamferPass(padded, offsets, true, &empty_rings_);
  ChamferPass(padded, offsets, false, &empty_rings_);
}

size_t PointGrid::PaddedBlock(int x, int y, int z) const {
  // Cells are >= 0 here, so the division floors.
  const size_t bx = static_cast<size_t>(x / kBlockCells + 1), by = static_cast<size_t>(y / kBlockCells + 1),
               bz = static_cast<size_t>(z / kBlockCells + 1);
  return (bz * static_cast<size_t>(block_dims_.y() + 2) + by) * static_cast<size_t>(block_dims_.x() + 2) + bx;
}

int PointGrid::FirstRing(const Eigen::Vector3i& cell) const {
  // A cell in a block k >= 1 blocks away is at least kBlockCells * (k - 1) + 1 cells away. From a cell
  // outside the grid: at least the chessboard distance to the grid, and at least the bound at the
  // nearest grid cell less that.
  const int x = std::clamp(cell.x(), 0, dims_.x() - 1), y = std::clamp(cell.y(), 0, dims_.y() - 1),
            z = std::clamp(cell.z(), 0, dims_.z() - 1);
  const int outside = std::max({std::abs(cell.x() - x), std::abs(cell.y() - y), std::abs(cell.z() - z)});
  const int blocks = empty_rings_[PaddedBlock(x, y, z)];
  const int inner = blocks == 0 ? 0 : kBlockCells * (blocks - 1) + 1;
  return std::max(outside, inner - outside);
}

void PointGrid::ScanRing(const Eigen::Vector3f& query, const Eigen::Vector3i& cell, int ring,
                         const Eigen::Vector3i& lo, const Eigen::Vector3i& hi, Best* best) const {
  // The best is kept in locals: through the pointer the compiler would reload it for every point (a
  // float* may alias the points).
  Best b = *best;
  // Cells x0..x1 of a row hold one contiguous run of points (the points are sorted by cell), so a run
  // of cells costs two loads however many of them are empty.
  const auto scan = [&](size_t row, int x0, int x1) {
    const uint32_t end = cell_start_[row + static_cast<size_t>(x1) + 1];
    for (uint32_t i = cell_start_[row + static_cast<size_t>(x0)]; i < end; ++i)
      Consider((points_[i] - query).squaredNorm(), i, &b);
  };
  for (int z = lo.z(); z <= hi.z(); ++z) {
    const bool z_face = std::abs(z - cell.z()) == ring;
    for (int y = lo.y(); y <= hi.y(); ++y) {
      const size_t row = CellIndex(0, y, z);
      if (z_face || std::abs(y - cell.y()) == ring) {
        scan(row, lo.x(), hi.x());
        continue;
      }
      // Inside the ring's z and y faces only its two x faces belong to the ring.
      if (cell.x() - ring >= lo.x()) scan(row, cell.x() - ring, cell.x() - ring);
      if (ring > 0 && cell.x() + ring <= hi.x()) scan(row, cell.x() + ring, cell.x() + ring);
    }
  }
  *best = b;
}

float PointGrid::Search(const Eigen::Vector3f& query, float margin_m, Best* best) const {
  const Eigen::Vector3f box_max = origin_ + dims_.cast<float>() * cell_m_;
  const float outside_m = (origin_ - query).cwiseMax(query - box_max).cwiseMax(0.0f).norm();
  if (!(outside_m < std::sqrt(best->sq) + margin_m)) return std::isnan(outside_m) ? 0.0f : outside_m;
  const Eigen::Vector3f g = (query - origin_) * inv_cell_;
  if (!(g.cwiseAbs().maxCoeff() < kMaxCellCoordinate)) {
    // A query this far from the grid: every point is examined.
    for (uint32_t i = 0; i < points_.size(); ++i) Consider((points_[i] - query).squaredNorm(), i, best);
    return std::numeric_limits<float>::infinity();
  }
  const Eigen::Vector3i cell = FloorCells(g);
  const Eigen::Vector3f frac = g - cell.cast<float>();
  // Cells from the query to the nearest face of its own cell: ring r >= 1 lies at least r - 1 + face away.
  const float face = std::min(frac.minCoeff(), 1.0f - frac.maxCoeff());
  for (int ring = FirstRing(cell);; ++ring) {
    // Every point within `radius` must be examined: the nearest, and the margin beyond it.
    const float radius_m = std::sqrt(best->sq) + margin_m;
    const float lower_cells = ring == 0 ? 0.0f : std::max(0.0f, ring - 1 + face - kSlackCells);
    if (lower_cells * cell_m_ >= radius_m) return radius_m;
    // Only cells that intersect the box around that ball can hold such a point.
    const float reach = std::min(radius_m * inv_cell_, 2 * kMaxCellCoordinate);
    Eigen::Vector3i ring_lo, ring_hi, lo, hi;
    for (int a = 0; a < 3; ++a) ring_lo[a] = std::max(cell[a] - ring, 0), ring_hi[a] = std::min(cell[a] + ring, dims_[a] - 1);
    BoxCells(g, reach, ring_lo, ring_hi, &lo, &hi);
    if ((lo.array() <= hi.array()).all()) ScanRing(query, cell, ring, lo, hi, best);
    if ((cell.array() - ring <= 0).all() && (cell.array() + ring >= dims_.array() - 1).all())
      return std::sqrt(best->sq) + margin_m;
  }
}

bool PointGrid::Nearest(const Eigen::Vector3d& query, double max_distance_m, size_t* index,
                        double* distance_sq_m2) const {
  size_t none = kNoHint;
  const bool found = NearestFrom(query, max_distance_m, &none, distance_sq_m2);
  if (found) *index = none;
  return found;
}

bool PointGrid::NearestFrom(const Eigen::Vector3d& query, double max_distance_m, size_t* index,
                            double* distance_sq_m2) const {
  double clear_m = 0.0;
  return NearestFrom(query, max_distance_m, 0.0, index, distance_sq_m2, &clear_m);
}

bool PointGrid::NearestFrom(const Eigen::Vector3d& query, double max_distance_m, double margin_m, size_t* index,
                            double* distance_sq_m2, double* clear_m) const {
  *clear_m = std::numeric_limits<double>::infinity();
  if (points_.empty()) return false;
  const Eigen::Vector3f q = query.cast<float>();
  Best best{static_cast<float>(max_distance_m * max_distance_m), kNone, std::numeric_limits<float>::infinity()};
  if (*index < points_.size()) {
    const float hint_sq = (points_[*index] - q).squaredNorm();
    if (hint_sq < best.sq) best = Best{hint_sq, static_cast<uint32_t>(*index), best.second_sq};
  }
  const float covered_m = Search(q, static_cast<float>(margin_m), &best);
  *clear_m = std::min(covered_m, std::sqrt(best.second_sq));
  if (best.index == kNone) return false;
  *index = best.index;
  *distance_sq_m2 = best.sq;
  return true;
}

bool PointGrid::AnyWithin(const Eigen::Vector3d& query, double radius_m) const {
  if (points_.empty()) return false;
  const Eigen::Vector3f q = query.cast<float>();
  // The same float arithmetic as Nearest, so that both agree on points at the radius.
  const float radius_sq = static_cast<float>(radius_m * radius_m);
  const Eigen::Vector3f g = (q - origin_) * inv_cell_;
  const float reach = static_cast<float>(radius_m) * inv_cell_ + kSlackCells;  // slack: the points' cells round too
  if (!(g.cwiseAbs().maxCoeff() + reach < kMaxCellCoordinate)) {
    size_t index = 0;
    double distance_sq = 0;
    return Nearest(query, radius_m, &index, &distance_sq);
  }
  Eigen::Vector3i lo, hi;
  BoxCells(g, reach, Eigen::Vector3i::Zero(), dims_ - Eigen::Vector3i::Ones(), &lo, &hi);
  if (!(lo.array() <= hi.array()).all()) return false;
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (uint32_t i = cell_start_[CellIndex(lo.x(), y, z)], end = cell_start_[CellIndex(hi.x(), y, z) + 1]; i < end; ++i)
        if ((points_[i] - q).squaredNorm() < radius_sq) return true;
  return false;
}

bool PointGrid::RadiusCells(const Eigen::Vector3f& query, float radius_m, Eigen::Vector3i* lo, Eigen::Vector3i* hi) const {
  const Eigen::Vector3f g = (query - origin_) * inv_cell_;
  const float reach = radius_m * inv_cell_;
  *lo = Eigen::Vector3i::Zero(), *hi = dims_ - Eigen::Vector3i::Ones();
  if (g.cwiseAbs().maxCoeff() + reach < kMaxCellCoordinate) BoxCells(g, reach, *lo, *hi, lo, hi);
  return (lo->array() <= hi->array()).all();
}

void PointGrid::Radius(const Eigen::Vector3d& query, double radius_m, std::vector<std::pair<size_t, float>>* out) const {
  out->clear();
  if (points_.empty()) return;
  const Eigen::Vector3f q = query.cast<float>();
  const float radius_sq = static_cast<float>(radius_m * radius_m);
  Eigen::Vector3i lo, hi;
  if (!RadiusCells(q, static_cast<float>(radius_m), &lo, &hi)) return;
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (uint32_t i = cell_start_[CellIndex(lo.x(), y, z)], end = cell_start_[CellIndex(hi.x(), y, z) + 1]; i < end; ++i) {
        const float d_sq = (points_[i] - q).squaredNorm();
        if (d_sq < radius_sq) out->emplace_back(i, d_sq);
      }
  std::sort(out->begin(), out->end(),
            [](const auto& a, const auto& b) { return a.second < b.second || (a.second == b.second && a.first < b.first); });
}

bool PointGrid::NearestUntaken(const Eigen::Vector3d& query, double radius_m, const std::vector<char>& taken,
                               double max_distance_sq_m2, size_t* index) const {
  if (points_.empty()) return false;
  const Eigen::Vector3f q = query.cast<float>();
  // Radius's float arithmetic, so that both agree on points at the radius and on ties.
  const float radius_sq = static_cast<float>(radius_m * radius_m);
  Eigen::Vector3i lo, hi;
  if (!RadiusCells(q, static_cast<float>(radius_m), &lo, &hi)) return false;
  float best_sq = radius_sq;
  uint32_t best = kNone;
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (uint32_t i = cell_start_[CellIndex(lo.x(), y, z)], end = cell_start_[CellIndex(hi.x(), y, z) + 1]; i < end; ++i) {
        const float d_sq = (points_[i] - q).squaredNorm();
        if (!(d_sq < radius_sq) || taken[i] || static_cast<double>(d_sq) > max_distance_sq_m2) continue;
        if (best == kNone || d_sq < best_sq || (d_sq == best_sq && i < best)) best_sq = d_sq, best = i;
      }
  if (best == kNone) return false;
  *index = best;
  return true;
}

}  // namespace mocap
