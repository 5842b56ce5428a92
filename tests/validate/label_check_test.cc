#include "validate/label_check.h"

#include <gtest/gtest.h>

#include "synthetic.h"

namespace mocap {
namespace {

using testing::Frame;
using testing::Kinect;

/// A depth frame and mask of the object at T_camera_object: dense surface samples splatted into the
/// camera with a per-pixel nearest-depth test, plus Kinect-like noise.
Frame RenderFrame(const TriangleMesh& mesh, const Rigid3d& T_camera_object, std::mt19937& rng) {
  const PinholeCamera camera = Kinect();
  Frame f{DepthImage(640, 480, 0.0f), LabelImage(640, 480, 0)};
  std::normal_distribution<double> noise(0.0, 0.001);
  for (const auto& p_model : SampleSurface(mesh, 0.0007)) {
    const Eigen::Vector3d p = T_camera_object * p_model;
    const auto px = camera.Project(p);
    if (!px) continue;
    const int u = static_cast<int>(std::lround(px->x())), v = static_cast<int>(std::lround(px->y()));
    if (!f.depth.contains(u, v)) continue;
    if (f.depth.at(u, v) == 0.0f || p.z() < f.depth.at(u, v)) {
      f.depth.at(u, v) = static_cast<float>(p.z());
      f.mask.at(u, v) = 3;
    }
  }
  for (auto& d : f.depth.data)
    if (d > 0) d += static_cast<float>(noise(rng));
  return f;
}

class LabelCheckTest : public ::testing::Test {
 protected:
  TriangleMesh mesh_ = testing::BoxMesh({0.16, 0.06, 0.21});
  SurfaceCropSource model_ = SurfaceCropSource::FromMesh(mesh_, CropOptions{});
  Rigid3d truth_ = Rigid3d::FromRvec({2.0, 0.3, 0.4}, {0.05, -0.03, 0.85});
  ValidateOptions options_;
  std::mt19937 rng_{9};
  Frame frame_ = RenderFrame(mesh_, truth_, rng_);

  LabelCheck Check(const Rigid3d& label) {
    return CheckLabelInFrame(frame_.depth, Kinect(), frame_.mask, 3, label, model_, {}, options_);
  }
};

TEST_F(LabelCheckTest, AcceptsTheTrueLabel) {
  const LabelCheck c = Check(truth_);
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_TRUE(c.success);
  EXPECT_TRUE(c.segicp_reliable);
  EXPECT_LT(c.errors.position_mm, 2.0);
  EXPECT_LT(c.errors.rotation_angle_deg, 1.0);
  EXPECT_GT(c.label_score, 0.9);
}

TEST_F(LabelCheckTest, FlagsAMountOffByOneCentimetre) {
  const Rigid3d label = truth_ * Rigid3d::FromRvec({0, 0, 0}, {0.01, 0, 0});
  const LabelCheck c = Check(label);
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_NEAR(c.errors.position_mm, 10.0, 2.0);
}

TEST_F(LabelCheckTest, FlagsAMountOffByFiveDegrees) {
  const Rigid3d label = truth_ * Rigid3d::FromRvec(Eigen::Vector3d(0.3, 1, 0.2).normalized() * RadFromDeg(5), {0, 0, 0});
  const LabelCheck c = Check(label);
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_NEAR(c.errors.rotation_angle_deg, 5.0, 1.0);
}

TEST_F(LabelCheckTest, RejectsALabelFiveCentimetresOff) {
  const LabelCheck c = Check(truth_ * Rigid3d::FromRvec({0, 0, 0}, {0.0, 0.05, 0.0}));
  EXPECT_EQ(c.verdict, Verdict::kReject) << c.reason;
  EXPECT_LT(c.label_score, 0.5);
}

TEST_F(LabelCheckTest, BadInputGivesAVerdictWithAReason) {
  const PinholeCamera camera = Kinect();
  LabelCheck c = CheckLabelInFrame(DepthImage{}, camera, frame_.mask, 3, truth_, model_, {}, options_);
  EXPECT_EQ(c.reason_code, VerdictReason::kNoDepth);
  EXPECT_EQ(c.verdict, Verdict::kSuspect);
  c = CheckLabelInFrame(frame_.depth, camera, LabelImage(320, 240, 3), 3, truth_, model_, {}, options_);
  EXPECT_EQ(c.reason_code, VerdictReason::kMaskSizeMismatch);
  EXPECT_NE(c.reason.find("320x240"), std::string::npos);
  c = CheckLabelInFrame(frame_.depth, camera, LabelImage(640, 480, 0), 3, truth_, model_, {}, options_);
  EXPECT_EQ(c.reason_code, VerdictReason::kEmptyMask);
  // A mask of 5x5 pixels: too few points.
  LabelImage small(640, 480, 0);
  const Eigen::Vector2d centre = *camera.Project(truth_.translation());
  for (int dv = -2; dv <= 2; ++dv)
    for (int du = -2; du <= 2; ++du) small.at(static_cast<int>(centre.x()) + du, static_cast<int>(centre.y()) + dv) = 3;
  c = CheckLabelInFrame(frame_.depth, camera, small, 3, truth_, model_, {}, options_);
  EXPECT_EQ(c.reason_code, VerdictReason::kTooFewPoints);
  EXPECT_FALSE(c.estimated);
  // Depth without valid pixels under the mask.
  c = CheckLabelInFrame(DepthImage(640, 480, 0.0f), camera, frame_.mask, 3, truth_, model_, {}, options_);
  EXPECT_EQ(c.reason_code, VerdictReason::kTooFewPoints);
}

TEST(Verdict, RulesFollowTheThresholds) {
  VerdictOptions o;
  LabelCheck c;
  c.segicp_reliable = true;
  c.errors = {4.0, 1.0, 2.0};
  DecideVerdict(o, &c);
  EXPECT_EQ(c.verdict, Verdict::kAccept);
  c.errors = {8.0, 1.0, 2.0};
  DecideVerdict(o, &c);
  EXPECT_EQ(c.verdict, Verdict::kSuspect);
  c.errors = {4.0, 1.0, 12.0};
  DecideVerdict(o, &c);
  EXPECT_EQ(c.verdict, Verdict::kReject);
  c.segicp_reliable = false;
  c.label_score = 0.2;
  DecideVerdict(o, &c);
  EXPECT_EQ(c.reason_code, VerdictReason::kLabelDoesNotFit);
  c.label_score = 0.8;
  DecideVerdict(o, &c);
  EXPECT_EQ(c.verdict, Verdict::kSuspect);
  EXPECT_EQ(ToString(c.reason_code), "no_reliable_estimate");
}

// An estimate on a handful of depth points checks nothing, whichever way it points: at close range the
// accuracy sweep's bottle, almost without depth, accepted a label on 3 points and rejected one on 4.
TEST(Verdict, AnEstimateOnTooFewPointsLeavesTheLabelUnchecked) {
  VerdictOptions o;
  LabelCheck c;
  c.estimated = c.segicp_reliable = true;
  c.observability.supported_points = o.min_supported_points - 1;
  for (const double position_mm : {1.0, 40.0}) {
    c.errors = {position_mm, 0.5, 0.5};
    DecideVerdict(o, &c);
    EXPECT_EQ(c.verdict, Verdict::kSuspect);
    EXPECT_EQ(c.reason_code, VerdictReason::kTooFewPoints) << c.reason;
    EXPECT_TRUE(IsBadInput(c.reason_code));
    EXPECT_NE(c.reason.find("29 depth points"), std::string::npos) << c.reason;
  }
  c.observability.supported_points = o.min_supported_points;
  DecideVerdict(o, &c);
  EXPECT_EQ(c.reason_code, VerdictReason::kDisagrees) << c.reason;
  c.errors = {1.0, 0.5, 0.5};
  DecideVerdict(o, &c);
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  o.min_supported_points = -1;
  EXPECT_THROW(o.check(), InputError);
}

// A hand holding the object puts points a centimetre in front of its surface, inside its mask (the
// labeller's visibility tolerance is about 2 cm). The robust point-to-plane fit gives them no weight.
TEST_F(LabelCheckTest, FingersOnTheSurfaceDoNotPullTheEstimate) {
  const PinholeCamera camera = Kinect();
  const Eigen::Vector2d centre = *camera.Project(truth_.translation());
  int fingers = 0;
  for (int v = static_cast<int>(centre.y()) - 10; v < static_cast<int>(centre.y()) + 40; ++v)
    for (int u = static_cast<int>(centre.x()) - 40; u < static_cast<int>(centre.x()) + 5; ++u)
      if (frame_.mask.contains(u, v) && frame_.mask.at(u, v) == 3 && frame_.depth.at(u, v) > 0) {
        frame_.depth.at(u, v) -= 0.012f;
        ++fingers;
      }
  ASSERT_GT(fingers, 1000);
  const LabelCheck robust = Check(truth_);
  EXPECT_EQ(robust.verdict, Verdict::kAccept) << robust.reason;
  EXPECT_LT(robust.errors.position_mm, 1.5) << robust.reason;
  EXPECT_LT(robust.errors.rotation_angle_deg, 0.5) << robust.reason;
  options_.observability.robust_sigmas = 0;  // least squares: the fingers count
  const LabelCheck plain = Check(truth_);
  EXPECT_GT(plain.errors.position_mm, robust.errors.position_mm + 0.3) << plain.reason;
}

// A hand between camera and object lies inside the label's mask (rendered from the known objects alone);
// the measured depth shows it 15 cm in front of the model's surface there, so those pixels leave the scene
// cloud and the crops. With the plain mask (occluder_margin_m = 0, the paper's) its points are the
// object's.
TEST_F(LabelCheckTest, AHandInFrontIsCutByTheMeasuredDepth) {
  const PinholeCamera camera = Kinect();
  const Eigen::Vector2d centre = *camera.Project(truth_.translation());
  int64_t hand = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = static_cast<int>(centre.x()) - 15; u < static_cast<int>(centre.x()) + 60; ++u)
      if (frame_.mask.contains(u, v) && frame_.mask.at(u, v) == 3 && frame_.depth.at(u, v) > 0) {
        frame_.depth.at(u, v) -= 0.15f;
        ++hand;
      }
  int64_t object = 0;
  for (uint16_t m : frame_.mask.data) object += m == 3;
  ASSERT_GT(hand, object / 3);
  const LabelCheck cut = Check(truth_);
  EXPECT_EQ(cut.verdict, Verdict::kAccept) << cut.reason;
  EXPECT_LT(cut.errors.position_mm, 2.0) << cut.reason;
  EXPECT_LE(cut.occluder_pixels, hand);  // the object's own pixels stay
  EXPECT_GT(cut.occluder_pixels, hand * 95 / 100);
  options_.occluder_margin_m = 0;
  const LabelCheck plain = Check(truth_);
  EXPECT_EQ(plain.occluder_pixels, 0);
  EXPECT_NE(plain.verdict, Verdict::kAccept) << plain.reason;
}

// A label a centimetre or two off keeps every pixel of the object: the cut takes only what lies the margin
// (3 cm) in front of the label's surface, so a wrong label is not excused by cutting the object away.
TEST_F(LabelCheckTest, TheDepthCutKeepsTheObjectUnderAWrongLabel) {
  const Eigen::Vector3d view = truth_.translation().normalized();
  for (const Rigid3d& label : {Rigid3d::FromRvec({0, 0, 0}, 0.02 * view) * truth_,
                               Rigid3d::FromRvec({0, 0, 0}, -0.02 * view) * truth_,
                               truth_ * Rigid3d::FromRvec(Eigen::Vector3d(0.3, 1, 0.2).normalized() * RadFromDeg(5), {0, 0, 0})}) {
    const std::optional<OccluderCut> cut =
        CutOccludersAtLabel(frame_.depth, Kinect(), frame_.mask, 3, label, model_, options_);
    EXPECT_FALSE(cut.has_value()) << cut->pixels;
  }
  // Moved 5 cm back, the label's surface lies behind the measured one by more than the margin: the
  // object's pixels in front of it are cut, the check has too little left and does not accept.
  const Rigid3d behind = Rigid3d::FromRvec({0, 0, 0}, 0.05 * view) * truth_;
  const LabelCheck c = Check(behind);
  EXPECT_GT(c.occluder_pixels, 0);
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
}

// The accept bounds follow the estimate's precision: a precise estimate is held to the floor (the
// label's own error), an imprecise one gets up to the widest bounds, one without analysis the widest.
TEST(Verdict, AcceptBoundsFollowTheEstimatesPrecision) {
  VerdictOptions o;
  LabelCheck c;
  c.segicp_reliable = true;
  c.errors = {4.0, 0.5, 0.5};
  DecideVerdict(o, &c);
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;  // not analysed: the widest bounds
  EXPECT_DOUBLE_EQ(c.accept_position_mm, 5.0);
  c.observability.analysed = true;
  c.observability.information = Eigen::Matrix<double, 6, 1>::Constant(0.3);
  c.observability.radius_m = 0.05;
  c.observability.supported_points = 3000;
  c.observability.residual_rms_m = 0.001;
  DecideVerdict(o, &c);
  EXPECT_NEAR(c.accept_position_mm, 1e3 * o.accept_floor_position_m, 0.2);
  EXPECT_NEAR(c.accept_rotation_deg, o.accept_floor_rotation_deg, 0.1);
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;  // 4 mm from a precise estimate
  EXPECT_NE(c.reason.find("accept bounds 2."), std::string::npos) << c.reason;
  c.observability.supported_points = 60;  // few points, noisy: the bounds widen to their limit
  c.observability.residual_rms_m = 0.006;
  DecideVerdict(o, &c);
  EXPECT_DOUBLE_EQ(c.accept_position_mm, 5.0);
  EXPECT_GT(c.precision.position_mm, 1.0);
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
}

// Far from a Kinect v1 the disparity step, not the noise, limits what the depth can tell: 3.5 mm from a
// precise estimate is a difference at 1 m and within half a step (6.9 mm) at 2.2 m. The floor says so
// in the bounds and the record; a 1 cm difference stays beyond the widest bound at any range.
TEST(Verdict, TheAcceptFloorTakesHalfTheDepthsResolution) {
  const auto step_m = [](double z_m) { return 2.85e-3 * z_m * z_m; };  // CameraStreamInfo::depth_step_m
  ValidateOptions o;
  LabelCheck c;
  c.estimated = c.segicp_reliable = true;
  c.errors = {3.5, 0.3, 0.3};
  c.observability.analysed = true;
  c.observability.information = Eigen::Matrix<double, 6, 1>::Constant(0.3);
  c.observability.radius_m = 0.1;
  c.observability.supported_points = 3000;
  c.observability.residual_rms_m = 0.001;
  ApplyDepthResolution({1.0 / 580, step_m(1.0)}, o, &c);
  EXPECT_NEAR(c.resolution_position_mm, std::hypot(0.86, 1.43), 0.01);
  EXPECT_NEAR(c.resolution_rotation_deg, DegFromRad(std::atan2(0.5e-3 / 0.58, 0.1)), 1e-9);
  EXPECT_NEAR(c.accept_position_mm, std::hypot(2.5, 0.86, 1.43), 0.1);
  EXPECT_EQ(c.verdict, Verdict::kSuspect) << c.reason;
  ApplyDepthResolution({2.2 / 580, step_m(2.2)}, o, &c);
  EXPECT_DOUBLE_EQ(c.accept_position_mm, 5.0);  // capped by the widest bound
  EXPECT_GT(c.accept_rotation_deg, 1.5 + 0.05);
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  c.errors = {10.0, 0.3, 0.3};
  DecideVerdict(o.verdict, &c);
  EXPECT_EQ(c.verdict, Verdict::kSuspect) << c.reason;
  LabelCheck none;  // no estimate: nothing to bound
  ApplyDepthResolution({2.2 / 580, step_m(2.2)}, o, &none);
  EXPECT_EQ(none.resolution_position_mm, 0.0);
}

TEST(PoseErrors, AreThePapersThree) {
  const Rigid3d a = Rigid3d::FromRvec({0, 0, RadFromDeg(30)}, {0, 0, 1});
  const Rigid3d b = Rigid3d::FromRvec({0, RadFromDeg(40), 0}, {0.003, 0.004, 1});
  const PoseErrors e = ComputePoseErrors(a, b);
  EXPECT_NEAR(e.position_mm, 5.0, 1e-9);
  EXPECT_NEAR(e.rotation_axis_deg, 90.0, 1e-9);
  EXPECT_NEAR(e.rotation_angle_deg, RotationDistanceDeg(a, b), 1e-12);
}

TEST(Symmetry, AnEstimateTurnedAboutTheAxisComparesAsTheLabel) {
  const SymmetryAxis axis{{0, 1, 0}, {0.02, 0, 0.01}};  // the axis through (0.02, 0, 0.01), along y
  const Rigid3d label = Rigid3d::FromRvec({0.3, -0.2, 0.5}, {0.1, 0.0, 0.9});
  const Rigid3d turn_about_axis = Rigid3d::FromRvec({0, 0, 0}, axis.point_object) *
                                  Rigid3d::FromRvec({0, RadFromDeg(70), 0}, {0, 0, 0}) *
                                  Rigid3d::FromRvec({0, 0, 0}, -axis.point_object);
  // Turned 70 deg about the axis, plus a small true error that the symmetry must not hide.
  const Rigid3d small_error = Rigid3d::FromRvec({RadFromDeg(2), 0, 0}, {0.001, 0, 0});
  const Rigid3d estimate = label * turn_about_axis * small_error;
  EXPECT_GT(RotationDistanceDeg(estimate, label), 60.0);
  const Rigid3d nearest = NearestSymmetricPose(estimate, label, axis);
  EXPECT_NEAR(RotationDistanceDeg(nearest, label), 2.0, 0.05);
  EXPECT_LT(TranslationDistanceM(nearest, label), 0.0015);
  // A rotation about another axis is not hidden.
  const Rigid3d tilted = label * Rigid3d::FromRvec({0, 0, RadFromDeg(10)}, {0, 0, 0});
  EXPECT_NEAR(RotationDistanceDeg(NearestSymmetricPose(tilted, label, axis), label), 10.0, 1e-6);
}

TEST(Symmetry, ADiscreteSymmetryAllowsOnlyItsSteps) {
  const SymmetryAxis half_turn{{0, 0, 1}, {0.01, 0, 0}, 180.0};  // a table: 180 deg about z through (1 cm, 0, 0)
  const Rigid3d label = Rigid3d::FromRvec({0.1, 0.2, -0.3}, {0.0, 0.1, 1.2});
  const auto about_axis = [&](double deg) {
    return Rigid3d::FromRvec({0, 0, 0}, half_turn.point_object) * Rigid3d::FromRvec({0, 0, RadFromDeg(deg)}, {0, 0, 0}) *
           Rigid3d::FromRvec({0, 0, 0}, -half_turn.point_object);
  };
  // 183 deg about the axis: the half turn hides 180 of them, not the remaining 3.
  const Rigid3d nearest = NearestSymmetricPose(label * about_axis(183), label, half_turn);
  EXPECT_NEAR(RotationDistanceDeg(nearest, label), 3.0, 1e-6);
  EXPECT_LT(TranslationDistanceM(nearest, label), 0.001);
  // 70 deg is no symmetry of a half-turn object: nothing is hidden.
  EXPECT_NEAR(RotationDistanceDeg(NearestSymmetricPose(label * about_axis(70), label, half_turn), label), 70.0, 1e-6);
}

}  // namespace
}  // namespace mocap
