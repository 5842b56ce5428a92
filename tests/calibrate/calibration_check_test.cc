#include "calibrate/calibration_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/check.h"
#include "synthetic.h"

namespace mocap {
namespace {

using test::ExpSO3;

/// A hand-held camera circling three static objects on a table for 8 s at 15 Hz, looking at the
/// middle one (it turns about all three axes); object "mug" is carried around from 2 s to 6 s.
struct Scene {
  static constexpr double kRateHz = 15, kSeconds = 8;
  Rigid3d T_world_camera(double t) const {
    const double a = 0.6 * std::sin(2 * M_PI * t / kSeconds) + 0.2 * t;
    const Eigen::Vector3d eye(0.9 * std::cos(a), 0.9 * std::sin(a), 0.5 + 0.1 * std::sin(1.3 * t));
    const Eigen::Vector3d z = (Eigen::Vector3d(0, 0, 0.05) - eye).normalized();
    const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized(), y = z.cross(x);
    Eigen::Matrix3d R;
    R << x, y, z;
    return Rigid3d(Eigen::Quaterniond(R) * ExpSO3(Eigen::Vector3d(0, 0, 0.2 * std::sin(0.9 * t))), eye);
  }
  Rigid3d T_world_mesh(int object, double t) const {
    const Eigen::Vector3d at[3] = {{-0.15, 0.05, 0.04}, {0.0, 0.0, 0.06}, {0.18, -0.08, 0.03}};
    Rigid3d T(ExpSO3(Eigen::Vector3d(0, 0, 0.7 * object)), at[object]);
    if (object == 2 && t > 2 && t < 6) {
      const double s = (t - 2) / 4 * 2 * M_PI;  // lifted, turned and put back
      T = Rigid3d(ExpSO3(Eigen::Vector3d(0.3 * std::sin(s), 0.2 * std::sin(2 * s), 0.8 * std::sin(s))) * T.rotation(),
                  T.translation() + Eigen::Vector3d(0.1 * std::sin(s), 0.05 * std::sin(2 * s), 0.12 * std::sin(0.5 * s)));
    }
    return T;
  }
  Rigid3d T_camera_mesh(int object, double t) const { return T_world_camera(t).inverse() * T_world_mesh(object, t); }
};

const char* const kObjects[3] = {"box", "drill", "mug"};

struct Faults {
  Rigid3d camera_D;            ///< E = D L for camera "kinect"
  Rigid3d object_O[3];         ///< E = L O
  double latency_error_s = 0;  ///< labels taken this much too late
};

/// Labels with the faults, SegICP estimates at the truth with AR(1) noise (0.8 mm, 0.25 deg, rho 0.7).
std::vector<CheckRecord> Records(const Faults& faults, unsigned seed) {
  const Scene scene;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  std::vector<CheckRecord> records;
  Eigen::Matrix<double, 6, 1> noise[3];
  for (auto& e : noise) e.setZero();
  for (int f = 0; f < static_cast<int>(Scene::kSeconds * Scene::kRateHz); ++f) {
    const double t = f / Scene::kRateHz;
    for (int k = 0; k < 3; ++k) {
      for (int i = 0; i < 6; ++i) noise[k](i) = 0.7 * noise[k](i) + std::sqrt(1 - 0.49) * n(rng);
      const Rigid3d truth = scene.T_camera_mesh(k, t);
      const Rigid3d estimate(ExpSO3(RadFromDeg(0.25) * noise[k].head<3>()) * truth.rotation(),
                             truth.translation() + 0.8e-3 * noise[k].tail<3>());
      const Rigid3d label = faults.camera_D.inverse() * scene.T_camera_mesh(k, t + faults.latency_error_s) *
                            faults.object_O[k].inverse();
      records.push_back({"kinect", kObjects[k], k + 1, static_cast<int64_t>(std::llround(t * 1e9)), label, estimate});
    }
  }
  return records;
}

TEST(CalibrationCheck, ReportsNothingWhenTheCalibrationIsRight) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const CalibrationCheckResult result = CheckCalibration(Records({}, seed));
    EXPECT_TRUE(result.findings.empty()) << "seed " << seed << ": " << ToString(result.findings[0].kind) << " "
                                         << result.findings[0].size_mm << " mm";
    EXPECT_EQ(result.records, 360);
    EXPECT_GT(result.records_with_motion, 350);
    EXPECT_GT(result.autocorrelation, 0.4);  // the AR(1) noise is seen and widens the intervals
  }
}

TEST(CalibrationCheck, NamesACameraMountErrorAndItsSize) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Faults faults;
    faults.camera_D = Rigid3d(ExpSO3(Eigen::Vector3d::Zero()), Eigen::Vector3d(0.003, -0.004, 0.0));  // 5 mm
    const CalibrationCheckResult result = CheckCalibration(Records(faults, seed));
    ASSERT_EQ(result.findings.size(), 1u) << "seed " << seed;
    const CheckFinding& f = result.findings[0];
    EXPECT_EQ(f.kind, CheckItemKind::kCameraMount);
    EXPECT_EQ(f.name, "kinect");
    EXPECT_NEAR(f.size_mm, 5.0, 0.5);
    EXPECT_LT(TranslationDistanceM(f.correction, faults.camera_D), 0.5e-3);
    EXPECT_GT(f.ci95_mm, 0.0);
    EXPECT_LT(f.ci95_mm, 1.0);
  }
}

TEST(CalibrationCheck, NamesAnObjectMountErrorAndItsSize) {
  for (unsigned seed : {1u, 2u, 3u}) {
    Faults faults;
    faults.object_O[1] = Rigid3d(ExpSO3(RadFromDeg(5) * Eigen::Vector3d(0.6, 0.0, 0.8)), Eigen::Vector3d(0.006, 0.0, -0.008));
    const CalibrationCheckResult result = CheckCalibration(Records(faults, seed));
    ASSERT_EQ(result.findings.size(), 1u) << "seed " << seed << " first: " << ToString(result.findings[0].kind);
    const CheckFinding& f = result.findings[0];
    EXPECT_EQ(f.kind, CheckItemKind::kObjectMount);
    EXPECT_EQ(f.name, "drill");
    EXPECT_NEAR(f.size_mm, 10.0, 1.0);
    EXPECT_NEAR(f.size_deg, 5.0, 0.5);
    EXPECT_LT(RotationDistanceDeg(f.correction, faults.object_O[1]), 0.3);
  }
}

TEST(CalibrationCheck, NamesALatencyErrorWithItsSign) {
  for (double error_s : {0.020, -0.020}) {
    Faults faults;
    faults.latency_error_s = error_s;
    const CalibrationCheckResult result = CheckCalibration(Records(faults, 5));
    ASSERT_GE(result.findings.size(), 1u) << error_s;
    const CheckFinding& f = result.findings[0];
    EXPECT_EQ(f.kind, CheckItemKind::kLatency);
    EXPECT_NEAR(f.latency_error_ms, 1e3 * error_s, 4.0);
    EXPECT_LT(f.latency_ci95_ms, 4.0);
  }
}

TEST(CalibrationCheck, AStaticSceneCannotTellCameraFromObjectMount) {
  // One object, camera and object still: E = D L = L O for O = inv(L) D L; both explain it, and the
  // warning says so.
  std::vector<CheckRecord> records;
  const Rigid3d L(ExpSO3(Eigen::Vector3d(0.2, 0.4, 0.1)), Eigen::Vector3d(0.05, 0.02, 0.8));
  const Rigid3d D(ExpSO3(Eigen::Vector3d::Zero()), Eigen::Vector3d(0.005, 0, 0));
  std::mt19937 rng(4);
  for (int i = 0; i < 60; ++i)
    records.push_back({"kinect", "box", 1, i * 33'000'000LL, L, test::Noisy(D * L, rng, 0.5e-3, 0.1)});
  const CalibrationCheckResult result = CheckCalibration(records);
  ASSERT_EQ(result.findings.size(), 1u);
  EXPECT_FALSE(result.findings[0].alike.empty());
  ASSERT_FALSE(result.warnings.empty());
  EXPECT_NE(result.warnings[0].find("almost equally well"), std::string::npos) << result.warnings[0];
}

/// Records of a fourth object, a 0.6 m table top at the scene's middle, as the validator reports a plane:
/// its estimate is measured along the top's normal and in its tilts, and is the label's in the top's
/// plane (slides and spin), where no depth point constrains it. `judged` says so when set.
std::vector<CheckRecord> TableRecords(const Faults& faults, const Rigid3d& table_O, bool judged, unsigned seed) {
  const Scene scene;
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  CheckRecord::Judged directions;
  directions.radius_m = 0.25;
  directions.directions = Eigen::Matrix<double, 6, 3>::Zero();
  directions.directions(0, 0) = directions.directions(1, 1) = directions.directions(5, 2) = 1;  // tilts, height
  std::vector<CheckRecord> records;
  for (int f = 0; f < static_cast<int>(Scene::kSeconds * Scene::kRateHz); ++f) {
    const double t = f / Scene::kRateHz;
    const Rigid3d T_world_table(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, -0.02));
    const Rigid3d truth = scene.T_world_camera(t).inverse() * T_world_table;
    const Rigid3d label = faults.camera_D.inverse() * truth * table_O.inverse();
    // The truth's difference from the label, object frame, kept in the judged directions only.
    const Rigid3d delta = label.inverse() * truth;
    Eigen::Vector3d w = delta.rvec(), v = delta.translation();
    w.z() = 0, v.x() = 0, v.y() = 0;
    const Rigid3d estimate_exact = label * Rigid3d::FromRvec(w, v);
    const Rigid3d estimate(ExpSO3(RadFromDeg(0.1) * Eigen::Vector3d(n(rng), n(rng), n(rng))) * estimate_exact.rotation(),
                           estimate_exact.translation() + 0.5e-3 * Eigen::Vector3d(n(rng), n(rng), n(rng)));
    records.push_back({"kinect", "table", 4, static_cast<int64_t>(std::llround(t * 1e9)), label, estimate});
    if (judged) records.back().judged = directions;
  }
  return records;
}

TEST(CalibrationCheck, MeasuresOnlyTheDirectionsTheDepthJudged) {
  Faults faults;
  faults.camera_D = Rigid3d(ExpSO3(Eigen::Vector3d::Zero()), Eigen::Vector3d(0.003, -0.004, 0.0));  // 5 mm
  for (const bool judged : {false, true}) {
    std::vector<CheckRecord> records = Records(faults, 1);
    const std::vector<CheckRecord> table = TableRecords(faults, Rigid3d(), judged, 2);
    records.insert(records.end(), table.begin(), table.end());
    const CalibrationCheckResult result = CheckCalibration(records);
    ASSERT_GE(result.findings.size(), 1u);
    EXPECT_EQ(result.findings[0].kind, CheckItemKind::kCameraMount);
    EXPECT_NEAR(result.findings[0].size_mm, 5.0, 0.5);
    // Read as measurements, the table's estimates held at the label in its plane come out as a table
    // mount that undoes the camera's shift there.
    if (!judged) {
      ASSERT_EQ(result.findings.size(), 2u);
      EXPECT_EQ(result.findings[1].name, "table");
      continue;
    }
    EXPECT_EQ(result.findings.size(), 1u) << result.findings.back().name << " " << result.findings.back().size_mm << " mm";
  }
  // A table mount off along its normal is measured, and only that part is reported and corrected.
  const Rigid3d table_O(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.0, 0.0, 0.008));
  std::vector<CheckRecord> records = Records({}, 3);
  const std::vector<CheckRecord> table = TableRecords({}, table_O, true, 4);
  records.insert(records.end(), table.begin(), table.end());
  const CalibrationCheckResult result = CheckCalibration(records);
  ASSERT_EQ(result.findings.size(), 1u);
  EXPECT_EQ(result.findings[0].name, "table");
  EXPECT_NEAR(result.findings[0].size_mm, 8.0, 0.5);
  EXPECT_LT(TranslationDistanceM(result.findings[0].correction, table_O), 0.5e-3);
}

TEST(CalibrationCheck, TooFewRecordsSayWhatToRecord) {
  std::vector<CheckRecord> records = Records({}, 1);
  records.resize(12);
  try {
    CheckCalibration(records);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too few reliable SegICP estimates: 12 (need 20)"), std::string::npos) << e.what();
  }
}

TEST(CalibrationCheck, OptionsAreChecked) {
  CalibrationCheckOptions options;
  options.similar_share = 1.5;
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.min_records = 2;
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.significance = 0;
  EXPECT_THROW(options.check(), InputError);
}

}  // namespace
}  // namespace mocap
