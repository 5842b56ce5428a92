// The estimate along directions only an object's outline constrains (validate/outline.h): a table top
// 0.4 x 0.3 m seen whole from 0.8 m, whose in-plane slide no surface normal resists. The frame's depth
// is the truth's; the mask is the label run's, rendered at the label.
#include "validate/outline.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "synthetic.h"
#include "validate/crop_cache.h"
#include "validate/label_check.h"

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
    return CheckLabelInFrame(frame_.depth, Kinect(), at_label.mask, 4, label, model_, {}, options_, mask_at_label);
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

}  // namespace
}  // namespace mocap
