// Degrees of freedom of a label check (validate/observability.h): a table top whose edges lie outside the
// image constrains only its height and tilt; a body of revolution everything but its spin; a box
// showing two faces everything, its slide along their common edge through its outline.
#include "validate/observability.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "synthetic.h"
#include "validate/crop_cache.h"
#include "validate/label_check.h"

namespace mocap {
namespace {

using testing::Frame;
using testing::Kinect;
using testing::Slab;
using testing::SplatFrame;

/// A cone of revolution about +z (a funnel's outside): radius 0.09 m at z = 0 to 0.02 m at z = 0.15 m.
TriangleMesh Cone() {
  TriangleMesh mesh;
  const int n = 64;
  for (int ring = 0; ring < 2; ++ring)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * std::numbers::pi * i / n, r = ring ? 0.02 : 0.09;
      mesh.vertices.push_back({r * std::cos(a), r * std::sin(a), ring ? 0.15 : 0.0});
    }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    mesh.triangles.push_back({i, j, n + j});
    mesh.triangles.push_back({i, n + j, n + i});
  }
  return mesh;
}

/// Depth of the plane z = 0 of the table frame, every pixel (the table fills the image), 1 mm noise.
Frame TableFrame(const Rigid3d& T_camera_table, std::mt19937& rng) {
  const PinholeCamera camera = Kinect();
  Frame f{DepthImage(640, 480, 0.0f), LabelImage(640, 480, 4)};
  const Eigen::Vector3d n = T_camera_table.rotation_matrix().col(2), p0 = T_camera_table.translation();
  std::normal_distribution<double> noise(0.0, 0.001);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const Eigen::Vector3d ray((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      f.depth.at(u, v) = static_cast<float>(n.dot(p0) / n.dot(ray) + noise(rng));  // z of the hit
    }
  return f;
}

class TableTest : public ::testing::Test {
 protected:
  // The camera 0.8 m above the table top, tilted 15 deg: the image sees the top only.
  Rigid3d T_camera_table_ = Rigid3d::FromRvec(Eigen::Vector3d(std::numbers::pi - RadFromDeg(15), 0, 0).eval(),
                                              {0.03, -0.02, 0.8});
  TriangleMesh mesh_ = Slab(2.4, 1.8, 0.03);
  SurfaceCropSource surface_ = SurfaceCropSource::FromMesh(mesh_, CropOptions{0.01});
  CachedCropSource model_{surface_, CropCacheOptions{}};
  ValidateOptions options_ = testing::OptionsWithCropPixel(0.01);
  std::mt19937 rng_{3};
  Frame frame_ = TableFrame(T_camera_table_, rng_);

  LabelCheck Check(const Rigid3d& label) {
    return CheckLabelInFrame(frame_.depth, Kinect(), frame_.mask, 4, label, model_, {}, options_);
  }
};

/// The unobservable directions of `o` split into their dominant parts: unit translations and unit
/// rotation axes (object frame).
struct Hidden {
  std::vector<Eigen::Vector3d> translations, rotations;
};
Hidden HiddenDirections(const Observability& o) {
  Hidden h;
  for (int k = 0; k < 6; ++k) {
    if (o.judged[k]) continue;
    const Eigen::Matrix<double, 6, 1> v = o.directions.col(k);
    if (v.head<3>().norm() > v.tail<3>().norm())
      h.rotations.push_back(v.head<3>().normalized());
    else
      h.translations.push_back(v.tail<3>().normalized());
  }
  return h;
}

bool Mentions(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& line : lines)
    if (line.find(text) != std::string::npos) return true;
  return false;
}

TEST_F(TableTest, ReportsItsInPlanePositionAndSpinUnobservable) {
  const LabelCheck c = Check(T_camera_table_);
  ASSERT_TRUE(c.observability.analysed);
  EXPECT_EQ(c.observability.observable, 3) << c.reason;
  // Two translations within the top's plane and the spin about its normal (+z of the table).
  const Hidden hidden = HiddenDirections(c.observability);
  ASSERT_EQ(hidden.translations.size(), 2u) << c.reason;
  ASSERT_EQ(hidden.rotations.size(), 1u) << c.reason;
  for (const Eigen::Vector3d& t : hidden.translations) EXPECT_LT(std::abs(t.z()), 0.1) << c.reason;
  EXPECT_GT(std::abs(hidden.rotations[0].z()), 0.95) << c.reason;
  EXPECT_TRUE(Mentions(c.observability.unobservable, "translation along any direction normal to")) << c.reason;
  EXPECT_TRUE(Mentions(c.observability.unobservable, "rotation about")) << c.reason;
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_EQ(c.reason_code, VerdictReason::kAgreesWhereObservable) << c.reason;
}

TEST_F(TableTest, FlagsACentimetreAlongItsNormal) {
  const LabelCheck c = Check(T_camera_table_ * Rigid3d::FromRvec({0, 0, 0}, {0, 0, 0.01}));
  EXPECT_NE(c.verdict, Verdict::kAccept) << c.reason;
  EXPECT_NEAR(c.observed.position_mm, 10.0, 1.5) << c.reason;
}

TEST_F(TableTest, ReportsACentimetreSlideInItsPlaneAsUnobservableNotAsAgreement) {
  const LabelCheck c = Check(T_camera_table_ * Rigid3d::FromRvec({0, 0, 0}, {0.007, 0.007, 0}));
  // Nothing the depth sees contradicts the label, and the record says what it could not see.
  EXPECT_EQ(c.reason_code, VerdictReason::kAgreesWhereObservable) << c.reason;
  EXPECT_NE(c.reason_code, VerdictReason::kAgrees);
  EXPECT_NE(c.reason.find("unobservable: translation along any direction normal to"), std::string::npos) << c.reason;
  EXPECT_LT(c.observed.position_mm, 2.0) << c.reason;
}

TEST_F(TableTest, ItsOutlineDoesNotBoundASlideWhenItsEdgesAreOutOfView) {
  // The session check's path: the mask is the label run's, here all table whichever way it slides.
  const Rigid3d label = T_camera_table_ * Rigid3d::FromRvec({0, 0, 0}, {0.007, 0.007, 0});
  const MaskAtLabel drawn{label};
  const LabelCheck c = CheckLabelInFrame(frame_.depth, Kinect(), frame_.mask, 4, label, model_, {}, options_, &drawn);
  ASSERT_FALSE(c.outline.empty()) << c.reason;
  for (const OutlineStep& step : c.outline) EXPECT_FALSE(step.judged) << c.reason;
  EXPECT_EQ(c.reason_code, VerdictReason::kAgreesWhereObservable) << c.reason;
  EXPECT_NE(c.reason.find("unobservable: translation along any direction normal to"), std::string::npos) << c.reason;
}

TEST_F(TableTest, ALabelSlidInItsPlaneKeepsTheEstimateAtTheLabelWhereTheDepthCannotTell) {
  // The top alone is in view: anywhere in its plane fits the depth equally. The label-seeded acquisition
  // settles the tie by nearness to the label, so the estimate does not wander along the plane.
  const Rigid3d label = T_camera_table_ * Rigid3d::FromRvec({0, 0, 0}, {0.007, 0.007, 0});
  options_.check_seed = AcquisitionSeed::kLabel;
  const LabelCheck c = Check(label);
  ASSERT_TRUE(c.estimated) << c.reason;
  EXPECT_LT(TranslationDistanceM(c.T_camera_object_segicp, label), 0.003) << c.reason;
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
}

/// The cone of revolution 0.7 m in front of the camera, tilted, with 1 mm depth noise.
struct ConeScene {
  TriangleMesh cone = Cone();
  SurfaceCropSource surface = SurfaceCropSource::FromMesh(cone, CropOptions{});
  CachedCropSource model{surface, CropCacheOptions{}};
  Rigid3d truth = Rigid3d::FromRvec({1.9, 0.2, 0.3}, {0.02, 0.01, 0.7});
  std::mt19937 rng{5};
  Frame frame = SplatFrame(cone, truth, rng);
};

TEST(Observability, ABodyOfRevolutionHidesOnlyItsSpin) {
  const ConeScene scene;
  const auto& [cone, surface, model, truth, rng, frame] = scene;
  const LabelCheck c = CheckLabelInFrame(frame.depth, Kinect(), frame.mask, 4, truth, model, {}, ValidateOptions{});
  ASSERT_TRUE(c.observability.analysed) << c.reason;
  EXPECT_EQ(c.observability.observable, 5) << c.reason;
  const Hidden hidden = HiddenDirections(c.observability);
  ASSERT_EQ(hidden.rotations.size(), 1u) << c.reason;
  EXPECT_GT(std::abs(hidden.rotations[0].z()), 0.98) << c.reason;  // the axis of revolution
  EXPECT_TRUE(Mentions(c.observability.unobservable, "rotation about")) << c.reason;
  EXPECT_EQ(c.verdict, Verdict::kAccept) << c.reason;
  // A spin about the axis changes nothing the depth sees: not judged; a 5 deg tilt is.
  const LabelCheck spun = CheckLabelInFrame(frame.depth, Kinect(), frame.mask, 4,
                                            truth * Rigid3d::FromRvec({0, 0, RadFromDeg(20)}, {0, 0, 0}), model, {}, ValidateOptions{});
  EXPECT_EQ(spun.verdict, Verdict::kAccept) << spun.reason;
  const LabelCheck tilted = CheckLabelInFrame(frame.depth, Kinect(), frame.mask, 4,
                                              truth * Rigid3d::FromRvec({RadFromDeg(5), 0, 0}, {0, 0, 0}), model, {}, ValidateOptions{});
  EXPECT_NE(tilted.verdict, Verdict::kAccept) << tilted.reason;
}

/// The same crop from every pose: unit tests of the analysis and the probe on a hand-made crop.
struct FixedCropSource : CropSource {
  ModelCrop crop;
  ModelCrop Crop(const Rigid3d&) const override { return crop; }
  const PointCloud& surface_model() const override { return crop.points_model; }
};

TEST(Observability, NoDirectionIsHiddenWhenEverySideConstrainsIt) {
  // Unit check of the analysis: a cube corner (three faces) constrains all six directions by normals.
  PointCloud points, normals;
  for (int face = 0; face < 3; ++face)
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p[(face + 1) % 3] = 0.005 * i;
        p[(face + 2) % 3] = 0.005 * j;
        points.push_back(p);
        normals.push_back(Eigen::Vector3d::Unit(face));
      }
  ModelCrop crop;
  crop.points_model = points;
  crop.normals_model = normals;
  const PointGrid scene(points);
  FixedCropSource source;
  source.crop = crop;
  const Observability o = AnalyseObservability(source, Rigid3d(), scene, ObservabilityOptions{});
  ASSERT_TRUE(o.analysed);
  EXPECT_EQ(o.observable, 6);
  EXPECT_TRUE(o.unobservable.empty());
  EXPECT_GT(o.information.minCoeff(), 0.01);
}

// The probe's evidence is points: a square 10 cm patch seen through 25 crop points loses its 5 edge
// points to a 1 cm slide (20 %, above probe_min_loss) and is not told apart from its slid self by them,
// while 441 points lose 42. Slide and spin are judged only in the second; height and tilt in both.
TEST(Observability, AProbeJudgesADirectionOnlyByEnoughLostPoints) {
  PointCloud scene_points;
  for (int i = 0; i <= 100; ++i)
    for (int j = 0; j <= 100; ++j) scene_points.push_back({0.001 * i - 0.05, 0.001 * j - 0.05, 0.0});
  const PointGrid scene(scene_points);
  const auto patch = [](int per_side) {
    FixedCropSource source;
    for (int i = 0; i < per_side; ++i)
      for (int j = 0; j < per_side; ++j) {
        const double step = 0.1 / (per_side - 1);
        source.crop.points_model.push_back({step * i - 0.05, step * j - 0.05, 0.0});
        source.crop.normals_model.push_back(Eigen::Vector3d::UnitZ());
      }
    return source;
  };
  const FixedCropSource sparse = patch(5), dense = patch(21);
  EXPECT_EQ(AnalyseObservability(dense, Rigid3d(), scene, ObservabilityOptions{}).observable, 6);
  const Observability few = AnalyseObservability(sparse, Rigid3d(), scene, ObservabilityOptions{});
  ASSERT_TRUE(few.analysed);
  EXPECT_EQ(few.observable, 3);
  EXPECT_GE(*std::max_element(few.probe_loss.begin(), few.probe_loss.end()), 0.03);
  ObservabilityOptions by_share_alone;
  by_share_alone.probe_min_lost_points = 0;
  EXPECT_EQ(AnalyseObservability(sparse, Rigid3d(), scene, by_share_alone).observable, 6);
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

/// An analysis made by hand: 400 supported points, radius 0.1 m, eigen-directions the identity.
Observability HandMadeAnalysis(double residual_rms_m) {
  Observability o;
  o.analysed = true;
  o.supported_points = 400;
  o.residual_rms_m = residual_rms_m;
  o.radius_m = 0.1;
  return o;
}

// PrecisionOf: sigma^2 = s^2 / (n lambda) per observable direction, unobservable ones left out, and a
// rotation moves a point away from the analysis centre by its lever arm.
TEST(Observability, PrecisionFollowsTheNormalEquations) {
  Observability o = HandMadeAnalysis(0.002);
  o.information << 0.5, 0.5, 0.5, 0.5, 0.5, 0.5;  // directions: identity, [L w; v]
  const EstimatePrecision at_centre = PrecisionOf(o, o.center_object, 1.0);
  // Translation: 3 directions of variance (2 mm)^2 / (400 * 0.5) each.
  EXPECT_NEAR(at_centre.position_mm, std::sqrt(3.0) * 2.0 / std::sqrt(200.0), 1e-9);
  EXPECT_NEAR(at_centre.rotation_deg, DegFromRad(std::sqrt(3.0) * 0.002 / std::sqrt(200.0) / 0.1), 1e-9);
  EXPECT_NEAR(PrecisionOf(o, o.center_object, 4.0).position_mm, 2.0 * at_centre.position_mm, 1e-9);
  EXPECT_GT(PrecisionOf(o, Eigen::Vector3d(0.3, 0, 0), 1.0).position_mm, at_centre.position_mm);
  o.judged = {true, true, true, false, false, true};  // two translations unobservable
  EXPECT_NEAR(PrecisionOf(o, o.center_object, 1.0).position_mm, 2.0 / std::sqrt(200.0), 1e-9);
  o.analysed = false;
  EXPECT_EQ(PrecisionOf(o, o.center_object, 1.0).position_mm, 0.0);
}

}  // namespace
}  // namespace mocap

namespace mocap {
namespace {

// A refinement that converged (its last step below refine_step_m) carries the normal equations at its
// result: probing them gives what a fresh analysis there gives (the label check skips the rebuild).
TEST(Observability, AConvergedRefinementCarriesTheAnalysisAtItsResult) {
  const TriangleMesh cone = Cone();
  const SurfaceCropSource surface = SurfaceCropSource::FromMesh(cone, CropOptions{});
  const CachedCropSource model(surface, CropCacheOptions{});
  const Rigid3d truth = Rigid3d::FromRvec({1.9, 0.2, 0.3}, {0.02, 0.01, 0.7});
  std::mt19937 rng(7);
  const Frame frame = SplatFrame(cone, truth, rng);
  const PointCloud scene = VoxelDownsample(DepthToPointsMasked(frame.depth, Kinect(), frame.mask, 4), 0.003);
  const PointGrid grid(scene);
  const Rigid3d start = truth * Rigid3d::FromRvec({RadFromDeg(1.5), 0, 0}, {0.003, -0.002, 0.002});
  const ObservabilityOptions options;
  const ModelCrop crop = model.Crop(start);
  const PlaneRefinement refined = RefinePointToPlane(crop, start, grid, options);
  ASSERT_TRUE(refined.converged);
  EXPECT_LT(refined.iterations, options.refine_iterations);
  EXPECT_LT(TranslationDistanceM(refined.T_camera_object, truth), 0.002);
  const Observability carried = ProbeObservability(model, crop, refined.T_camera_object, grid, options, refined.observability);
  const Observability fresh = AnalyseObservability(model, refined.T_camera_object, grid, options, &crop);
  ASSERT_TRUE(carried.analysed && fresh.analysed);
  EXPECT_EQ(carried.observable, fresh.observable);
  EXPECT_EQ(carried.unobservable, fresh.unobservable);
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(carried.information(k), fresh.information(k), 0.02 * fresh.information(k) + 1e-4) << k;
  EXPECT_NEAR(carried.residual_rms_m, fresh.residual_rms_m, 1e-4);
}

TEST(Observability, RejectsANonPositiveRefinementStop) {
  ObservabilityOptions options;
  options.refine_step_m = 0.0;
  EXPECT_THROW(options.check(), InputError);
  options = ObservabilityOptions{};
  options.polish_step_m = -1e-4;
  EXPECT_THROW(options.check(), InputError);
  options.polish_step_m = std::nan("");
  EXPECT_THROW(options.check(), InputError);
}

// LeaveOutDirection: the left-out direction joins the unjudged ones, the judged ones stay orthonormal
// and keep their information, and a difference along the left-out direction is no longer judged.
TEST(Observability, ALeftOutDirectionIsNoLongerJudged) {
  Observability o = HandMadeAnalysis(0.001);
  o.information << 0.2, 0.3, 0.4, 0.5, 0.6, 0.7;
  o.judged = {false, true, true, true, true, true};  // the first (a rotation about x) already unjudged
  SummariseObservability(&o);
  ASSERT_EQ(o.observable, 5);
  const Eigen::Matrix<double, 6, 6> A = o.directions * o.information.asDiagonal() * o.directions.transpose();
  Eigen::Matrix<double, 6, 1> u;
  u << 0, 0, 0, 0.3, -0.4, 0.866;  // a translation, not along any eigen-direction
  LeaveOutDirection(&o, u);
  EXPECT_EQ(o.observable, 4);
  EXPECT_TRUE((o.directions.transpose() * o.directions).isIdentity(1e-9));
  for (int k = 0; k < 6; ++k) {
    const Eigen::Matrix<double, 6, 1> d = o.directions.col(k);
    if (o.judged[k]) {
      EXPECT_NEAR(d.dot(u), 0.0, 1e-9);                      // the judged ones lie across u
      EXPECT_NEAR(o.information(k), d.dot(A * d), 1e-9);     // with their information in A
    }
  }
  // 5 mm along u is not judged; 5 mm across it still is.
  const Eigen::Vector3d along = u.tail<3>().normalized(), across = along.cross(Eigen::Vector3d::UnitX()).normalized();
  EXPECT_LT(ObservedPart(o, Rigid3d::FromRvec(Eigen::Vector3d::Zero(), 0.005 * along), Rigid3d()).position_mm, 1e-6);
  EXPECT_NEAR(ObservedPart(o, Rigid3d::FromRvec(Eigen::Vector3d::Zero(), 0.005 * across), Rigid3d()).position_mm, 5.0, 1e-6);
  // Leaving it out again, or leaving out an unjudged direction, changes nothing.
  const Observability once = o;
  LeaveOutDirection(&o, u);
  EXPECT_EQ(o.observable, 4);
  EXPECT_TRUE(o.directions.isApprox(once.directions));
}

// LeaveOutRange (objects.yaml tof_range_biased on a time-of-flight camera): a label off along the
// camera's ray is no longer flagged, one off across the ray still is.
TEST(Observability, ARangeBiasedObjectIsJudgedAcrossTheRayOnly) {
  const ConeScene scene;
  const auto& [cone, surface, model, truth, rng, frame] = scene;
  const Eigen::Vector3d ray = truth.translation().normalized();
  const Eigen::Vector3d across = ray.cross(Eigen::Vector3d::UnitY()).normalized();
  const ValidateOptions options;
  auto check = [&](const Eigen::Vector3d& offset_m) {
    const Rigid3d label = Rigid3d::FromRvec(Eigen::Vector3d::Zero(), offset_m) * truth;
    LabelCheck c = CheckLabelInFrame(frame.depth, Kinect(), frame.mask, 4, label, model, {}, options);
    const Verdict before = c.verdict;
    LeaveOutRange(label, Eigen::Vector3d::Zero(), options, &c);
    return std::pair{before, c};
  };
  const auto [along_before, along] = check(0.008 * ray);
  EXPECT_NE(along_before, Verdict::kAccept) << along.reason;
  EXPECT_EQ(along.verdict, Verdict::kAccept) << along.reason;
  EXPECT_EQ(along.reason_code, VerdictReason::kAgreesWhereObservable) << along.reason;
  EXPECT_NE(along.reason.find("tof_range_biased"), std::string::npos) << along.reason;
  const auto [across_before, off] = check(0.008 * across);
  EXPECT_NE(across_before, Verdict::kAccept) << off.reason;
  EXPECT_NE(off.verdict, Verdict::kAccept) << off.reason;
}

}  // namespace
}  // namespace mocap
