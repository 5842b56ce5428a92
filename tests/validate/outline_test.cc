// The estimate along directions only an object's outline constrains (validate/outline.h): a table top
// 0.4 x 0.3 m seen whole from 0.8 m, whose in-plane slide no surface normal resists. The frame's depth
// is the truth's; the mask is the label run's, rendered at the label. And an object whose time-of-flight
// range is biased (OutlineFrame::range_biased): its estimate fitted with the push (validate/range_push.h),
// or, where none is found, its position across the ray taken from the outline.
#include "validate/outline.h"

#include <gtest/gtest.h>

#include <functional>
#include <numbers>
#include <random>

#include "synthetic.h"
#include "validate/crop_cache.h"
#include "validate/label_check.h"
#include "validate/range_push.h"

namespace mocap {
namespace {

using testing::Frame;
using testing::Kinect;

class OutlineTest : public ::testing::Test {
 protected:
  Rigid3d truth_ = Rigid3d::FromRvec(Eigen::Vector3d(std::numbers::pi - RadFromDeg(20), 0, 0).eval(), {0.02, -0.03, 0.8});
  TriangleMesh mesh_ = testing::Slab(0.4, 0.3, 0.03);
  SurfaceCropSource surface_ = SurfaceCropSource::FromMesh(mesh_, CropOptions{0.01});
  CachedCropSource model_{surface_, CropCacheOptions{}};
  ValidateOptions options_ = testing::OptionsWithCropPixel(0.01);
  std::mt19937 rng_{7};
  Frame frame_ = testing::SplatFrame(mesh_, truth_, rng_);

  /// The check of `label` with the label run's mask drawn at it.
  LabelCheck Check(const Rigid3d& label, bool mask_at_label = true) {
    std::mt19937 rng(1);
    const Frame at_label = testing::SplatFrame(mesh_, label, rng);
    const MaskAtLabel drawn{label};
    return CheckLabelInFrame(frame_.depth, Kinect(), at_label.mask, 4, label, model_, {}, options_,
                             mask_at_label ? &drawn : nullptr);
  }
};

/// The estimate's in-plane offset from the truth (the table's x-y), metres.
double InPlaneOffset(const Rigid3d& estimate, const Rigid3d& truth) {
  const Eigen::Vector3d d = (truth.inverse() * estimate).translation();
  return std::hypot(d.x(), d.y());
}

TEST_F(OutlineTest, AcceptsTheTrueLabelWithItsSlideJudgedByTheOutline) {
  const LabelCheck c = Check(truth_);
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  ASSERT_FALSE(c.outline.empty()) << c.reason;
  for (const OutlineStep& step : c.outline) EXPECT_TRUE(step.judged) << c.reason;
  EXPECT_LT(InPlaneOffset(c.T_camera_object_segicp, truth_), 0.002) << c.reason;
}

TEST_F(OutlineTest, FindsTheTableWhereALabelSlidACentimetreInItsPlaneIsNot) {
  for (const Eigen::Vector3d& slide : {Eigen::Vector3d(0.01, 0, 0), Eigen::Vector3d(0, -0.01, 0), Eigen::Vector3d(0.007, 0.007, 0)}) {
    const Rigid3d label = truth_ * Rigid3d::FromRvec({0, 0, 0}, slide);
    const LabelCheck c = Check(label);
    EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
    EXPECT_LT(InPlaneOffset(c.T_camera_object_segicp, truth_), 0.003) << c.reason;
    EXPECT_NEAR(c.observed.position_mm, 10.0, 3.0) << c.reason;
  }
}

TEST_F(OutlineTest, IsNotMadeWhenTheMaskIsNotTheLabels) {
  const LabelCheck c = Check(truth_ * Rigid3d::FromRvec({0, 0, 0}, {0.01, 0, 0}), false);
  EXPECT_TRUE(c.outline.empty()) << c.reason;
}

/// The estimate's offset from `truth` across the camera's ray through its origin, mm.
double AcrossRayMm(const Rigid3d& T, const Rigid3d& truth) {
  const Eigen::Vector3d ray = truth.translation().normalized();
  const Eigen::Vector3d d = T.translation() - truth.translation();
  return 1e3 * (d - d.dot(ray) * ray).norm();
}

/// An object on a time-of-flight camera: each surface point's range pushed back by up to 2.4 cm, the more
/// the more grazing the view (the simulator's multipath model, kinect2_model.cc), while each pixel still
/// sees the object or not as before; checked with the label run's mask drawn at the label.
class RangePushedScene {
 public:
  /// The surface normal (model frame) at a surface point of the mesh.
  using NormalOf = std::function<Eigen::Vector3d(const Eigen::Vector3d& p_model)>;

  RangePushedScene(TriangleMesh mesh, NormalOf normal_of, const Rigid3d& truth, double noise_m)
      : mesh_(std::move(mesh)), normal_of_(std::move(normal_of)), truth_(truth), noise_m_(noise_m) {}

  /// The object seen at `T_camera_object`; its range biased when `push_m` > 0.
  testing::Frame Seen(const Rigid3d& T_camera_object, double push_m) const {
    std::mt19937 rng(1);
    return testing::SplatFrame(mesh_, T_camera_object, rng, [&](const Eigen::Vector3d& p_model, const Eigen::Vector3d& p) {
      const Eigen::Vector3d n = T_camera_object.rotation() * normal_of_(p_model);
      return push_m * (1.0 - std::abs(n.dot(p.normalized())));
    }, noise_m_);
  }

  /// The check of `label` in the truth's frame pushed 24 mm at grazing views, as a range-biased object or not.
  LabelCheck Check(const Rigid3d& label, bool range_biased) const {
    const testing::Frame frame = Seen(truth_, 0.024), at_label = Seen(label, 0.0);
    const MaskAtLabel drawn{label, range_biased};
    LabelCheck c = CheckLabelInFrame(frame.depth, Kinect(), at_label.mask, 4, label, model_, {}, options_, &drawn);
    if (range_biased) LeaveOutRange(label, Eigen::Vector3d::Zero(), options_, &c);
    return c;
  }

  const Rigid3d& truth() const { return truth_; }

  /// The truth moved 1 cm across the ray through its origin.
  Rigid3d OffAcrossTheRay() const {
    const Eigen::Vector3d ray = truth_.translation().normalized();
    return {truth_.rotation(), truth_.translation() + 0.01 * ray.cross(Eigen::Vector3d::UnitX()).normalized()};
  }

 private:
  TriangleMesh mesh_;
  NormalOf normal_of_;
  Rigid3d truth_;
  double noise_m_;
  SurfaceCropSource surface_ = SurfaceCropSource::FromMesh(mesh_, CropOptions{});
  CachedCropSource model_{surface_, CropCacheOptions{}};
  ValidateOptions options_;
};

/// A box the size of the oil bottle, without noise: its flat faces each keep one incidence, so the range
/// push fit finds no push and the outline takes its position across the ray.
class RangeBiasedTest : public ::testing::Test {
 protected:
  static Eigen::Vector3d BoxNormal(const Eigen::Vector3d& p_model) {
    // The face's normal: the axis along which the point lies on the box's side.
    const Eigen::Vector3d size_m(0.10, 0.07, 0.20);
    int axis = 0;
    p_model.cwiseQuotient(size_m).cwiseAbs().maxCoeff(&axis);
    return Eigen::Vector3d::Unit(axis) * (p_model[axis] > 0 ? 1 : -1);
  }

  RangePushedScene box_{testing::BoxMesh({0.10, 0.07, 0.20}), BoxNormal,
                        Rigid3d::FromRvec({0.35, 0.75, 0.1}, {0.06, 0.03, 0.75}), 0.0};
};

TEST_F(RangeBiasedTest, TakesThePositionAcrossTheRayFromTheOutline) {
  const LabelCheck fit = box_.Check(box_.truth(), false), outline = box_.Check(box_.truth(), true);
  ASSERT_TRUE(fit.estimated && outline.estimated) << fit.reason << " / " << outline.reason;
  EXPECT_EQ(outline.range_push_mm, 0.0) << outline.reason;
  int across = 0;
  for (const OutlineStep& step : outline.outline) across += step.across_ray && step.judged;
  EXPECT_EQ(across, 2) << outline.reason;
  // The rigid fit of the deformed surface is off sideways; the outline is not.
  EXPECT_GT(AcrossRayMm(fit.T_camera_object_segicp, box_.truth()), 1.5) << fit.reason;
  EXPECT_LT(AcrossRayMm(outline.T_camera_object_segicp, box_.truth()), 0.7) << outline.reason;
  EXPECT_EQ(outline.verdict, Verdict::kAccept) << outline.reason;
}

TEST_F(RangeBiasedTest, FlagsALabelACentimetreOffAcrossTheRay) {
  const LabelCheck c = box_.Check(box_.OffAcrossTheRay(), true);
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_LT(AcrossRayMm(c.T_camera_object_segicp, box_.truth()), 2.0) << c.reason;
}

// The visible half of an elliptic cylinder (semi-axes 6 and 4 cm, 20 cm tall: a jug's body, whose turn
/// about its axis the ellipse pins) seen by a time-of-flight camera centred at `tof_center` (the check's
/// camera frame), its range pushed back by 24 mm (1 - cos theta) along each of that camera's rays, theta
/// the incidence on that ray, and 0.8 mm noise: the crop (model frame) and the measured points.
struct PushedCylinder {
  ModelCrop crop;
  PointCloud scene_camera;
};

PushedCylinder SeenPushed(const Rigid3d& truth, const Eigen::Vector3d& tof_center) {
  PushedCylinder out;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.0008);
  for (double z = -0.1; z <= 0.1; z += 0.004)
    for (double a = 0; a < 2 * M_PI; a += 0.03) {
      const Eigen::Vector3d p(0.06 * std::cos(a), 0.04 * std::sin(a), z);
      const Eigen::Vector3d n = Eigen::Vector3d(std::cos(a) / 0.06, std::sin(a) / 0.04, 0).normalized();
      const Eigen::Vector3d p_camera = truth * p, ray = (p_camera - tof_center).normalized();
      const double cos_theta = -(truth.rotation() * n).dot(ray);
      if (cos_theta < std::cos(RadFromDeg(80))) continue;  // back side, or too grazing to return
      out.crop.points_model.push_back(p), out.crop.normals_model.push_back(n);
      out.scene_camera.push_back(p_camera + (0.024 * (1 - cos_theta) + noise(rng)) * ray);
    }
  return out;
}

// The rigid point-to-plane fit of the pushed cylinder turns and shifts it; fitted with the push, it
// comes back.
TEST(RangePush, FittedWithThePushTheDeformedSurfaceComesBack) {
  const Rigid3d truth = Rigid3d::FromRvec({1.9, 0.3, -0.4}, {0.08, -0.05, 0.8});
  const PushedCylinder seen = SeenPushed(truth, Eigen::Vector3d::Zero());
  const PointGrid grid(seen.scene_camera);
  const Rigid3d start = truth * Rigid3d::FromRvec({0, 0, RadFromDeg(1.0)}, {0.002, 0.0, 0.0});
  ObservabilityOptions observability;
  const PlaneRefinement rigid = RefinePointToPlane(seen.crop, start, grid, observability);
  const RangePushFit fit = FitWithRangePush(seen.crop, start, grid, Eigen::Vector3d::Zero(), RangePushOptions{}, observability);
  std::printf("rigid: %.2f deg, %.2f mm across the ray; with the push (%.1f mm): %.2f deg, %.2f mm\n",
              RotationDistanceDeg(rigid.T_camera_object, truth), AcrossRayMm(rigid.T_camera_object, truth), 1e3 * fit.push_m,
              RotationDistanceDeg(fit.T_camera_object, truth), AcrossRayMm(fit.T_camera_object, truth));
  EXPECT_NEAR(fit.push_m, 0.024, 0.006);
  EXPECT_GT(RotationDistanceDeg(rigid.T_camera_object, truth), 1.2);
  EXPECT_GT(AcrossRayMm(rigid.T_camera_object, truth), 1.5);
  EXPECT_LT(RotationDistanceDeg(fit.T_camera_object, truth), 0.5 * RotationDistanceDeg(rigid.T_camera_object, truth));
  EXPECT_LT(AcrossRayMm(fit.T_camera_object, truth), 0.5);
  // No push in the depth: none found, the fit as the rigid one.
  PointCloud flat;
  for (const Eigen::Vector3d& p : seen.crop.points_model) flat.push_back(truth * p);
  const RangePushFit none = FitWithRangePush(seen.crop, start, PointGrid(flat), Eigen::Vector3d::Zero(), RangePushOptions{}, observability);
  EXPECT_LT(none.push_m, 0.001);
  EXPECT_LT(RotationDistanceDeg(none.T_camera_object, truth), 0.1);
}

// A Kinect v2's depth camera sits about 5 cm beside the colour camera the check is in (5.2 cm in the
// simulated one, sim/kinect2_model.cc): the push lies along the depth camera's rays, and fitted along
// the colour camera's it leaves the cylinder turned.
TEST(RangePush, LiesAlongTheDepthCamerasRays) {
  const Rigid3d truth = Rigid3d::FromRvec({1.9, 0.3, -0.4}, {0.08, -0.05, 0.8});
  const Eigen::Vector3d tof_center(-0.052, 0.0, 0.0);
  const PushedCylinder seen = SeenPushed(truth, tof_center);
  const PointGrid grid(seen.scene_camera);
  const Rigid3d start = truth * Rigid3d::FromRvec({0, 0, RadFromDeg(1.0)}, {0.002, 0.0, 0.0});
  ObservabilityOptions observability;
  const RangePushFit depth_rays = FitWithRangePush(seen.crop, start, grid, tof_center, RangePushOptions{}, observability);
  const RangePushFit color_rays = FitWithRangePush(seen.crop, start, grid, Eigen::Vector3d::Zero(), RangePushOptions{}, observability);
  std::printf("along the depth camera's rays: %.2f deg, %.2f mm across; along the colour camera's: %.2f deg, %.2f mm\n",
              RotationDistanceDeg(depth_rays.T_camera_object, truth), AcrossRayMm(depth_rays.T_camera_object, truth),
              RotationDistanceDeg(color_rays.T_camera_object, truth), AcrossRayMm(color_rays.T_camera_object, truth));
  EXPECT_NEAR(depth_rays.push_m, 0.024, 0.006);
  EXPECT_LT(RotationDistanceDeg(depth_rays.T_camera_object, truth), 1.0);
  EXPECT_LT(AcrossRayMm(depth_rays.T_camera_object, truth), 0.5);
  EXPECT_GT(RotationDistanceDeg(color_rays.T_camera_object, truth), 2 * RotationDistanceDeg(depth_rays.T_camera_object, truth));
  EXPECT_GT(AcrossRayMm(color_rays.T_camera_object, truth), 2 * AcrossRayMm(depth_rays.T_camera_object, truth));
}

/// A jug as SeenPushed's, flatter (semi-axes 7 and 3.5 cm: at 6 by 4 cm the check leaves its spin
/// unjudged), as a mesh with caps, with 0.8 mm noise.
Eigen::Vector3d JugNormal(const Eigen::Vector3d& p_model) {
  if (std::abs(std::abs(p_model.z()) - 0.1) < 1e-6) return {0, 0, p_model.z() > 0 ? 1.0 : -1.0};
  return Eigen::Vector3d(p_model.x() / (0.07 * 0.07), p_model.y() / (0.035 * 0.035), 0).normalized();
}

// With the push fitted the estimate is not biased across the ray, so the outline does not move it there
// (EstimateAlongOutline's across_ray): the true label is accepted, one a centimetre off across the ray is not.
TEST(RangePushedCheck, TakesTheFitWithItsPushAndNoMoveAcrossTheRay) {
  const RangePushedScene jug(testing::EllipticCylinderMesh(0.07, 0.035, 0.2), JugNormal,
                             Rigid3d::FromRvec({1.9, 0.3, -0.4}, {0.08, -0.05, 0.8}), 0.0008);
  const LabelCheck c = jug.Check(jug.truth(), true);
  ASSERT_TRUE(c.estimated) << c.reason;
  EXPECT_GT(c.range_push_mm, 10.0) << c.reason;
  for (const OutlineStep& step : c.outline) EXPECT_FALSE(step.across_ray) << c.reason;
  std::printf("with the push (%.1f mm): %.2f deg, %.2f mm across the ray\n", c.range_push_mm,
              RotationDistanceDeg(c.T_camera_object_segicp, jug.truth()), AcrossRayMm(c.T_camera_object_segicp, jug.truth()));
  EXPECT_LT(AcrossRayMm(c.T_camera_object_segicp, jug.truth()), 1.0) << c.reason;
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  const LabelCheck flagged = jug.Check(jug.OffAcrossTheRay(), true);
  EXPECT_NE(flagged.verdict, Verdict::kAccept) << flagged.reason;
}

}  // namespace
}  // namespace mocap
