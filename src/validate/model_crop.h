#pragma once
// Model crops: the side of an object model that a camera sees from a given pose (the paper's "model
// crop": "rendering the visible object's model at various azimuth and elevation angles and cropping
// the model to keep only the front face").
//
// CropSource is the seam between the validator and whatever produces crops. SurfaceCropSource computes
// them on the CPU from points sampled on the model surface with a z-buffer; a renderer-backed source
// (depth rendered by the EGL renderer at the same pose, back-projected into the model frame) plugs in
// by implementing the same interface.
#include <Eigen/Core>
#include <vector>

#include "core/rigid3.h"
#include "validate/point_cloud.h"

namespace mocap {

/// A crop: visible model points, in the model frame, and where it was seen from.
struct ModelCrop {
  PointCloud points_model;
  /// Unit surface normals of points_model (same order), model frame; empty when the source computes
  /// none (CachedCropSource adds them; the observability analysis estimates them otherwise).
  PointCloud normals_model;
  /// The camera pose the crop was computed for (model into camera).
  Rigid3d T_camera_model;
  /// Unit vector from the model origin towards the camera, model frame.
  Eigen::Vector3d view_direction_model = Eigen::Vector3d::UnitZ();
};

class CropSource {
 public:
  virtual ~CropSource() = default;
  /// The model points visible from a camera at its origin looking along +z when the model sits at
  /// `T_camera_model`. Thread-safe (called from parallel hypotheses).
  virtual ModelCrop Crop(const Rigid3d& T_camera_model) const = 0;
  /// The same crop, whose normals may be left out: for callers that use none (the acquisition's
  /// hypotheses, the alignment score, the observability probe), so that a source that computes normals
  /// (CachedCropSource) does so only for the crops that need them.
  virtual ModelCrop CropPoints(const Rigid3d& T_camera_model) const { return Crop(T_camera_model); }
  /// All surface points of the model (model frame), for bounding boxes.
  virtual const PointCloud& surface_model() const = 0;
};

/// A source's crops without normals (CropSource::CropPoints), for code that asks only Crop (the
/// acquisition). `base` must outlive it.
class PointsOnlyCropSource : public CropSource {
 public:
  explicit PointsOnlyCropSource(const CropSource& base) : base_(base) {}
  ModelCrop Crop(const Rigid3d& T_camera_model) const override { return base_.CropPoints(T_camera_model); }
  const PointCloud& surface_model() const override { return base_.surface_model(); }

 private:
  const CropSource& base_;
};

/// Triangle mesh in the model frame, metres.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> triangles;  ///< vertex indices
  /// Throws InputError when an index is out of range or the mesh is empty.
  void check() const;
};

/// Points on every triangle, on a grid along two of its edges with steps of at most `spacing_m` (vertices
/// and edges included), each surface point once (the samples triangles share at their vertices and edges are not
/// repeated). Deterministic.
PointCloud SampleSurface(const TriangleMesh& mesh, double spacing_m);

struct CropOptions {
  /// Size of a z-buffer pixel on the object, metres: one crop point per pixel (the crop's resolution).
  double pixel_m = 0.005;
  /// The session check coarsens pixel_m (and the scene voxels) for an object whose largest bounding-box
  /// face holds more than this many pixels, to about this many (a table top).
  int max_points = 4000;
  void check() const;
};

/// Hidden-surface removal by a z-buffer: surface samples are projected into a virtual pinhole camera
/// at T_camera_model whose pixel covers `pixel_m` at the model's distance; per pixel the nearest sample
/// is kept. Samples must be denser than pixel_m (SampleSurface at pixel_m / 2), otherwise back faces
/// show through holes in the front.
class SurfaceCropSource : public CropSource {
 public:
  SurfaceCropSource(PointCloud surface_model, const CropOptions& options);
  static SurfaceCropSource FromMesh(const TriangleMesh& mesh, const CropOptions& options);

  ModelCrop Crop(const Rigid3d& T_camera_model) const override;
  const PointCloud& surface_model() const override { return surface_; }

 private:
  PointCloud surface_;
  CropOptions options_;
  Eigen::Vector3d center_model_;  ///< surface centroid: sets the pixel scale
  Box3d box_model_;               ///< bounds the pixels a crop can cover (a dense z-buffer)
};

/// Camera poses on a view sphere around the model centre: `count` viewing directions spread evenly
/// (a Fibonacci lattice) over elevations in [min_elevation_deg, max_elevation_deg] (elevation measured
/// from the model x-y plane towards +z, azimuth about +z), each looking at `center_model` from
/// `distance_m` with the model +z axis pointing up in the image (-y) where possible.
std::vector<Rigid3d> ViewSpherePoses(int count, double min_elevation_deg, double max_elevation_deg,
                                     const Eigen::Vector3d& center_model, double distance_m);

/// The camera pose at `eye_model` looking at `target_model`, image-up along `up_model` (model frame).
Rigid3d LookAt(const Eigen::Vector3d& eye_model, const Eigen::Vector3d& target_model, const Eigen::Vector3d& up_model);

}  // namespace mocap
