#pragma once
// Model crops computed once per object and view, not once per record. What a camera sees of a rigid
// model depends only on where the camera centre lies in the model frame (its direction and, through
// perspective, a little on its distance); the camera's roll about that ray only turns the z-buffer's
// pixel grid. So crops are cached per cell of viewing direction (a cube map of about
// `direction_step_deg`) and per distance band, and every request falling in a cell gets that cell's
// crop, with its surface normals (for the observability analysis, validate/observability.h). A cell's
// normals are estimated on the first request that wants them (Crop, not CropPoints): most cells serve
// only the acquisition's hypotheses, which use none.
#include <cstdint>
#include <memory>
#include <mutex>
#include <unordered_map>

#include "validate/model_crop.h"

namespace mocap {

struct CropCacheOptions {
  /// Angular size of a direction cell, degrees: a crop is computed from the cell's centre, so the
  /// silhouette of a request can be off by up to half of it.
  double direction_step_deg = 2.0;
  /// Distance bands grow geometrically by this ratio (perspective changes the silhouette slowly).
  double distance_ratio = 1.25;
  /// Radius of the neighbourhood whose principal axes give a crop point's normal, metres (a few crop
  /// pixels of CropOptions::pixel_m).
  double normal_radius_m = 0.012;
  void check() const;
};

/// Cache statistics (for the benchmark and the run's diagnostics).
struct CropCacheStats {
  int64_t requests = 0;
  int64_t computed = 0;  ///< crops computed (cells filled)
};

class CachedCropSource : public CropSource {
 public:
  /// `base` must outlive the cache. Thread-safe: parallel requests of one cell may compute it twice,
  /// the first stored wins.
  CachedCropSource(const CropSource& base, const CropCacheOptions& options);
  /// The crop of the cell the camera centre falls in, with normals; T_camera_model is the request's.
  ModelCrop Crop(const Rigid3d& T_camera_model) const override;
  /// The cell's crop without normals.
  ModelCrop CropPoints(const Rigid3d& T_camera_model) const override;
  const PointCloud& surface_model() const override { return base_.surface_model(); }
  CropCacheStats stats() const;

 private:
  struct Cell {
    PointCloud points_model;
    Eigen::Vector3d eye_model, view_direction_model;
    mutable std::once_flag normals_once;  ///< normals_model is filled once, by the first Crop
    mutable PointCloud normals_model;
  };
  std::shared_ptr<const Cell> Compute(int64_t key, const Eigen::Vector3d& direction, double distance_m) const;
  /// The cell of a request (computed when new); the request's crop with the cell's points, no normals.
  std::shared_ptr<const Cell> Find(const Rigid3d& T_camera_model, ModelCrop* crop) const;

  const CropSource& base_;
  CropCacheOptions options_;
  Eigen::Vector3d center_model_;
  int cells_per_edge_ = 1;
  mutable std::mutex mutex_;
  mutable std::unordered_map<int64_t, std::shared_ptr<const Cell>> cells_;
  mutable CropCacheStats stats_;
};

/// Unit normals of a sampled surface: per point, the axis of least spread of its neighbours within
/// `radius_m` (principal axes); oriented towards `toward_model` (a viewpoint). A point with fewer
/// than 3 neighbours gets the direction towards the viewpoint.
PointCloud EstimateNormals(const PointCloud& points, double radius_m, const Eigen::Vector3d& toward_model);

}  // namespace mocap
