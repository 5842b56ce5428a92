// The session-wide step of `mocaplabel validate` (pipeline/session_wide.h) on validations built by hand:
// two cameras circling three static objects, SegICP estimates at the truth with correlated noise, labels
// with or without a camera-mount error. No renderer: the step reads only the records.
#include "pipeline/session_wide.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace mocap::pipeline {
namespace {

const char* const kCameras[2] = {"left", "right"};
const char* const kObjects[3] = {"box", "drill", "mug"};

/// Camera c at time t circles the objects (radius 0.9 m, turning and bobbing: every direction moves).
Rigid3d TCameraObject(int camera, int object, double t) {
  const double a = 0.6 * std::sin(0.8 * t) + 0.25 * t + M_PI * camera;
  const Eigen::Vector3d eye(0.9 * std::cos(a), 0.9 * std::sin(a), 0.5 + 0.1 * std::sin(1.3 * t + camera));
  const Eigen::Vector3d z = (Eigen::Vector3d(0, 0, 0.05) - eye).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized(), y = z.cross(x);
  Eigen::Matrix3d R;
  R << x, y, z;
  const Rigid3d T_world_camera(R, eye);
  const Eigen::Vector3d at[3] = {{-0.15, 0.05, 0.04}, {0.0, 0.0, 0.06}, {0.18, -0.08, 0.03}};
  const Rigid3d T_world_object(Eigen::Quaterniond(Eigen::AngleAxisd(0.7 * object, Eigen::Vector3d::UnitZ())), at[object]);
  return T_world_camera.inverse() * T_world_object;
}

/// 8 s at 15 Hz per camera; the labels of camera "left" carry `left_mount_error` (E = D L), every record
/// accepted but every 10th, rejected. Estimates: truth with AR(1) noise (0.8 mm, 0.25 deg, rho 0.7).
SessionValidation Validation(const Rigid3d& left_mount_error, unsigned seed, int frames = 120,
                             const Rigid3d& drill_mount_error = Rigid3d::Identity()) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  SessionValidation v;
  Eigen::Matrix<double, 6, 1> noise[2][3];
  for (auto& camera : noise)
    for (auto& e : camera) e.setZero();
  for (int f = 0; f < frames; ++f) {
    for (int c = 0; c < 2; ++c) {
      for (int k = 0; k < 3; ++k) {
        Eigen::Matrix<double, 6, 1>& e = noise[c][k];
        for (int i = 0; i < 6; ++i) e(i) = 0.7 * e(i) + std::sqrt(1 - 0.49) * n(rng);
        const double t = f / 15.0;
        const Rigid3d truth = TCameraObject(c, k, t);
        RecordCheck r;
        r.camera = kCameras[c], r.index = f, r.stamp_ns = static_cast<int64_t>(std::llround(t * 1e9));
        r.object = k + 1, r.name = kObjects[k], r.instance = k + 1;
        r.T_camera_object_label = (c == 0 ? left_mount_error.inverse() * truth : truth) * (k == 1 ? drill_mount_error : Rigid3d());
        r.check.estimated = r.check.segicp_reliable = true;
        const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.25 * M_PI / 180 * e.head<3>().norm(), e.head<3>().normalized()));
        r.check.T_camera_object_segicp = Rigid3d(turn * truth.rotation(), truth.translation() + 0.8e-3 * e.tail<3>());
        const bool rejected = f % 10 == 0;
        r.check.verdict = rejected ? Verdict::kReject : Verdict::kAccept;
        r.check.reason_code = rejected ? VerdictReason::kDisagrees : VerdictReason::kAgrees;
        r.check.reason = rejected ? "SegICP differs by 25 mm" : "SegICP agrees";
        v.records.push_back(r);
      }
    }
  }
  v.summary = Summarise(v.records, static_cast<int64_t>(v.records.size()));
  return v;
}

std::vector<ValidationObject> Objects() {
  std::vector<ValidationObject> objects;
  for (int k = 0; k < 3; ++k) objects.push_back({k + 1, kObjects[k], "", 1.0, std::nullopt});
  return objects;
}

TEST(SessionWide, ChangesNothingWhenTheCalibrationIsRight) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SessionValidation v = Validation(Rigid3d::Identity(), seed);
    EXPECT_TRUE(FlagSessionWideErrors(v, Objects(), {}).empty()) << "seed " << seed;
    ASSERT_TRUE(v.summary.session_wide);
    EXPECT_TRUE(v.summary.session_wide->ran);
    EXPECT_TRUE(v.summary.session_wide->findings.empty()) << v.summary.session_wide->findings[0];
    EXPECT_EQ(v.summary.verdicts["accept"], 648);
  }
}

TEST(SessionWide, AFiveMillimetreCameraMountFlagsThatCamerasAcceptedLabelsOnly) {
  for (unsigned seed : {1u, 2u, 3u}) {
    SessionValidation v = Validation(Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.003, -0.004, 0.0)), seed);
    const std::vector<size_t> flagged = FlagSessionWideErrors(v, Objects(), {});
    EXPECT_EQ(flagged.size(), 324u) << "seed " << seed;  // left's 360 records but its 36 rejected ones
    for (const RecordCheck& r : v.records) {
      if (r.camera == "right") {
        EXPECT_EQ(r.check.reason_code, r.index % 10 == 0 ? VerdictReason::kDisagrees : VerdictReason::kAgrees);
      } else if (r.index % 10 == 0) {
        EXPECT_EQ(r.check.verdict, Verdict::kReject);  // a reject stays a reject
      } else {
        EXPECT_EQ(r.check.verdict, Verdict::kSuspect);
        EXPECT_EQ(r.check.reason_code, VerdictReason::kCameraMountOff);
        EXPECT_NE(r.check.reason.find("together find camera_mount left "), std::string::npos) << r.check.reason;
        EXPECT_NE(r.check.reason.find("this record alone: SegICP agrees"), std::string::npos) << r.check.reason;
      }
    }
    EXPECT_EQ(v.summary.verdicts["accept"], 324);
    EXPECT_EQ(v.summary.verdicts["suspect"], 324);
    EXPECT_EQ(v.summary.reasons["camera_mount_off"], 324);
    ASSERT_TRUE(v.summary.session_wide);
    EXPECT_EQ(v.summary.session_wide->records_flagged, 324);
    ASSERT_EQ(v.summary.session_wide->findings.size(), 1u);
    EXPECT_EQ(v.summary.session_wide->findings[0].rfind("camera_mount left", 0), 0u) << v.summary.session_wide->findings[0];
  }
}

TEST(SessionWide, ACentimetreObjectMountFlagsThatObjectsAcceptedLabelsOnly) {
  const Rigid3d one_cm(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.006, 0.0, -0.008));
  for (unsigned seed : {1u, 2u, 3u}) {
    SessionValidation v = Validation(Rigid3d::Identity(), seed, 120, one_cm);
    const std::vector<size_t> flagged = FlagSessionWideErrors(v, Objects(), {});
    EXPECT_EQ(flagged.size(), 216u) << "seed " << seed;  // the drill's 240 records but its 24 rejected ones
    for (const RecordCheck& r : v.records) {
      if (r.name != "drill" || r.index % 10 == 0) {
        EXPECT_NE(r.check.verdict, Verdict::kSuspect) << r.name << " " << r.index;
      } else {
        EXPECT_EQ(r.check.reason_code, VerdictReason::kObjectMountOff);
        EXPECT_NE(r.check.reason.find("together find object_mount drill "), std::string::npos) << r.check.reason;
        EXPECT_NE(r.check.reason.find("every label of this object carries it"), std::string::npos) << r.check.reason;
      }
    }
    EXPECT_EQ(v.summary.reasons["object_mount_off"], 216);
  }
}

TEST(SessionWide, AnObjectMountWithinTheRecordsBoundsOrDeclaredRangeBiasedFlagsNothing) {
  // 3 mm: found, but within the widest per-record bounds (5 mm), which the records judge themselves.
  SessionValidation small = Validation(Rigid3d::Identity(), 1, 120, Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.003, 0, 0)));
  EXPECT_TRUE(FlagSessionWideErrors(small, Objects(), {}).empty());
  ASSERT_TRUE(small.summary.session_wide);
  EXPECT_EQ(small.summary.session_wide->findings.size(), 1u);
  // 1 cm on an object whose time-of-flight range is declared biased: its finding can be that bias.
  std::vector<ValidationObject> objects = Objects();
  objects[1].tof_range_biased = true;
  SessionValidation declared = Validation(Rigid3d::Identity(), 1, 120, Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.006, 0.0, -0.008)));
  EXPECT_TRUE(FlagSessionWideErrors(declared, objects, {}).empty());
  EXPECT_EQ(declared.summary.session_wide->findings.size(), 1u);
}

TEST(SessionWide, TooFewReliableRecordsSayWhyItDidNotRun) {
  SessionValidation v = Validation(Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.003, -0.004, 0.0)), 1, 3);
  EXPECT_TRUE(FlagSessionWideErrors(v, Objects(), {}).empty());
  ASSERT_TRUE(v.summary.session_wide);
  EXPECT_FALSE(v.summary.session_wide->ran);
  EXPECT_EQ(v.summary.session_wide->why_not, "18 records with a reliable estimate; the session-wide check needs 20");
  EXPECT_EQ(v.summary.verdicts["accept"], 12);
}

}  // namespace
}  // namespace mocap::pipeline
