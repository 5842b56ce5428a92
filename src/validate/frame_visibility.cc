#include "validate/frame_visibility.h"

#include <cmath>

#include "core/check.h"

namespace mocap {

VisibleInFrameCropSource::VisibleInFrameCropSource(const CropSource& base, const PinholeCamera& camera,
                                                   const DepthImage& depth_m, const LabelImage& mask,
                                                   uint16_t label_id, double occluder_margin_m)
    : base_(base), camera_(camera), depth_m_(depth_m), mask_(mask), label_id_(label_id), margin_m_(occluder_margin_m) {
  MOCAP_CHECK(depth_m.width == camera.width && depth_m.height == camera.height, "depth and camera sizes differ");
  MOCAP_CHECK(mask.width == depth_m.width && mask.height == depth_m.height, "depth and mask sizes differ");
}

ModelCrop VisibleInFrameCropSource::Crop(const Rigid3d& T_camera_model) const {
  return Visible(T_camera_model, base_.Crop(T_camera_model));
}

ModelCrop VisibleInFrameCropSource::CropPoints(const Rigid3d& T_camera_model) const {
  return Visible(T_camera_model, base_.CropPoints(T_camera_model));
}

ModelCrop VisibleInFrameCropSource::Visible(const Rigid3d& T_camera_model, ModelCrop crop) const {
  PointCloud visible, normals;
  visible.reserve(crop.points_model.size());
  const bool has_normals = crop.normals_model.size() == crop.points_model.size();
  // The rotation as a matrix once per crop: applying the quaternion costs twice the arithmetic per point.
  const Eigen::Matrix3d R = T_camera_model.rotation_matrix();
  const Eigen::Vector3d t = T_camera_model.translation();
  // Without distortion, PinholeCamera::Project's arithmetic in place of its call (the same pixels).
  const bool pinhole = !camera_.has_distortion();
  for (size_t i = 0; i < crop.points_model.size(); ++i) {
    const Eigen::Vector3d& p_model = crop.points_model[i];
    const Eigen::Vector3d p_camera = R * p_model + t;
    int u = -1, v = -1;
    if (pinhole) {
      if (p_camera.z() <= 0) continue;
      u = NearestPixel(camera_.fx * (p_camera.x() / p_camera.z()) + camera_.cx);
      v = NearestPixel(camera_.fy * (p_camera.y() / p_camera.z()) + camera_.cy);
    } else {
      const auto pixel = camera_.Project(p_camera);
      if (!pixel) continue;
      u = NearestPixel(pixel->x()), v = NearestPixel(pixel->y());
    }
    if (!depth_m_.contains(u, v)) continue;  // outside the image: the frame cannot see it
    const float measured_m = depth_m_.at(u, v);
    const uint16_t owner = mask_.at(u, v);
    // A labelled pixel without depth (nearer than the sensor's range, dark, shiny): nothing there can
    // confirm or deny the point, which another object there may well hide. A depthless background pixel
    // still counts: a point moved onto it has left the object's outline.
    if (owner != 0 && !(measured_m > 0)) continue;
    const bool hidden = owner != label_id_ && measured_m > 0 && measured_m < p_camera.z() - margin_m_;
    if (hidden) continue;  // something else in front
    visible.push_back(p_model);
    if (has_normals) normals.push_back(crop.normals_model[i]);
  }
  crop.points_model = std::move(visible);
  crop.normals_model = std::move(normals);
  return crop;
}

}  // namespace mocap
