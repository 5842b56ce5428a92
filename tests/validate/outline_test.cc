// The estimate along directions only an object's outline constrains (validate/outline.h): a table top
// 0.4 x 0.3 m seen whole from 0.8 m, whose in-plane slide no surface normal resists. The frame's depth
// is the truth's; the mask is the label run's, rendered at the label. And the position across the ray of an
// object whose time-of-flight range is biased (OutlineFrame::range_biased).
#include "validate/outline.h"

#include <gtest/gtest.h>

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

/// A box the size of the oil bottle on a time-of-flight camera: each surface point's range pushed back by
/// up to 2.4 cm, the more the more grazing the view (the simulator's multipath model, kinect2_model.cc),
/// while each pixel still sees the box or not as before.
class RangeBiasedTest : public ::testing::Test {
 protected:
  Eigen::Vector3d size_m_{0.10, 0.07, 0.20};
  Rigid3d truth_ = Rigid3d::FromRvec({0.35, 0.75, 0.1}, {0.06, 0.03, 0.75});
  TriangleMesh mesh_ = testing::BoxMesh(size_m_);
  SurfaceCropSource surface_ = SurfaceCropSource::FromMesh(mesh_, CropOptions{});
  CachedCropSource model_{surface_, CropCacheOptions{}};
  ValidateOptions options_;

  /// The box seen at `T_camera_object`, without noise; its range biased when `push_m` > 0.
  testing::Frame Seen(const Rigid3d& T_camera_object, double push_m) const {
    std::mt19937 rng(1);
    return testing::SplatFrame(mesh_, T_camera_object, rng, [&](const Eigen::Vector3d& p_model, const Eigen::Vector3d& p) {
      // The face's normal: the axis along which the point lies on the box's side.
      int axis = 0;
      p_model.cwiseQuotient(size_m_).cwiseAbs().maxCoeff(&axis);
      const Eigen::Vector3d n = T_camera_object.rotation() * (Eigen::Vector3d::Unit(axis) * (p_model[axis] > 0 ? 1 : -1));
      return push_m * (1.0 - std::abs(n.dot(p.normalized())));
    }, 0.0);
  }

  LabelCheck Check(const Rigid3d& label, bool range_biased) {
    const testing::Frame frame = Seen(truth_, 0.024), at_label = Seen(label, 0.0);
    const MaskAtLabel drawn{label, range_biased};
    LabelCheck c = CheckLabelInFrame(frame.depth, Kinect(), at_label.mask, 4, label, model_, {}, options_, &drawn);
    if (range_biased) LeaveOutRange(label, options_, &c);
    return c;
  }

  /// The estimate's offset from the truth across the camera's ray through the box's centre, metres.
  double AcrossRay(const Rigid3d& estimate) const {
    const Eigen::Vector3d ray = truth_.translation().normalized();
    const Eigen::Vector3d d = estimate.translation() - truth_.translation();
    return (d - d.dot(ray) * ray).norm();
  }
};

TEST_F(RangeBiasedTest, TakesThePositionAcrossTheRayFromTheOutline) {
  const LabelCheck fit = Check(truth_, false), outline = Check(truth_, true);
  ASSERT_TRUE(fit.estimated && outline.estimated) << fit.reason << " / " << outline.reason;
  int across = 0;
  for (const OutlineStep& step : outline.outline) across += step.across_ray && step.judged;
  EXPECT_EQ(across, 2) << outline.reason;
  // The rigid fit of the deformed surface is off sideways; the outline is not.
  EXPECT_GT(AcrossRay(fit.T_camera_object_segicp), 0.0015) << fit.reason;
  EXPECT_LT(AcrossRay(outline.T_camera_object_segicp), 0.0007) << outline.reason;
  EXPECT_EQ(outline.verdict, Verdict::kAccept) << outline.reason;
}

TEST_F(RangeBiasedTest, FlagsALabelACentimetreOffAcrossTheRay) {
  const Eigen::Vector3d ray = truth_.translation().normalized();
  const Eigen::Vector3d across = ray.cross(Eigen::Vector3d::UnitX()).normalized();
  const Rigid3d label(truth_.rotation(), truth_.translation() + 0.01 * across);
  const LabelCheck c = Check(label, true);
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_LT(AcrossRay(c.T_camera_object_segicp), 0.002) << c.reason;
}

// The visible half of an elliptic cylinder (semi-axes 6 and 4 cm, 20 cm tall: a jug's body, whose turn
// about its axis the ellipse pins) 0.8 m away, its range pushed back by 24 mm (1 - cos theta) along each
// ray. The rigid point-to-plane fit turns and shifts it; fitted with the push, it comes back.
TEST(RangePush, FittedWithThePushTheDeformedSurfaceComesBack) {
  const Rigid3d truth = Rigid3d::FromRvec({1.9, 0.3, -0.4}, {0.08, -0.05, 0.8});
  ModelCrop crop;
  PointCloud scene;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.0008);
  for (double z = -0.1; z <= 0.1; z += 0.004)
    for (double a = 0; a < 2 * M_PI; a += 0.03) {
      const Eigen::Vector3d p(0.06 * std::cos(a), 0.04 * std::sin(a), z);
      const Eigen::Vector3d n = Eigen::Vector3d(std::cos(a) / 0.06, std::sin(a) / 0.04, 0).normalized();
      const Eigen::Vector3d p_camera = truth * p, ray = p_camera.normalized();
      const double cos_theta = -(truth.rotation() * n).dot(ray);
      if (cos_theta < std::cos(RadFromDeg(80))) continue;  // back side, or too grazing to return
      crop.points_model.push_back(p), crop.normals_model.push_back(n);
      scene.push_back(p_camera + (0.024 * (1 - cos_theta) + noise(rng)) * ray);
    }
  const PointGrid grid(scene);
  const Rigid3d start = truth * Rigid3d::FromRvec({0, 0, RadFromDeg(1.0)}, {0.002, 0.0, 0.0});
  ObservabilityOptions observability;
  const PlaneRefinement rigid = RefinePointToPlane(crop, start, grid, observability);
  const RangePushFit fit = FitWithRangePush(crop, start, grid, RangePushOptions{}, observability);
  const Eigen::Vector3d ray = truth.translation().normalized();
  const auto across_mm = [&](const Rigid3d& T) {
    const Eigen::Vector3d d = T.translation() - truth.translation();
    return 1e3 * (d - d.dot(ray) * ray).norm();
  };
  std::printf("rigid: %.2f deg, %.2f mm across the ray; with the push (%.1f mm): %.2f deg, %.2f mm\n",
              RotationDistanceDeg(rigid.T_camera_object, truth), across_mm(rigid.T_camera_object), 1e3 * fit.push_m,
              RotationDistanceDeg(fit.T_camera_object, truth), across_mm(fit.T_camera_object));
  EXPECT_NEAR(fit.push_m, 0.024, 0.006);
  EXPECT_GT(RotationDistanceDeg(rigid.T_camera_object, truth), 1.2);
  EXPECT_GT(across_mm(rigid.T_camera_object), 1.5);
  EXPECT_LT(RotationDistanceDeg(fit.T_camera_object, truth), 0.5 * RotationDistanceDeg(rigid.T_camera_object, truth));
  EXPECT_LT(across_mm(fit.T_camera_object), 0.5);
  // No push in the depth: none found, the fit as the rigid one.
  PointCloud flat;
  for (const Eigen::Vector3d& p : crop.points_model) flat.push_back(truth * p);
  const RangePushFit none = FitWithRangePush(crop, start, PointGrid(flat), RangePushOptions{}, observability);
  EXPECT_LT(none.push_m, 0.001);
  EXPECT_LT(RotationDistanceDeg(none.T_camera_object, truth), 0.1);
}

}  // namespace
}  // namespace mocap
