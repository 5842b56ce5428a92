// The session check on a simulated Kinect1 recording (the default scenario's bottle carry; measured
// depth with the sensor model's noise, quantisation and invalid pixels; a moving camera; a hand that
// briefly occludes): correct labels meet the accuracy targets, and labels made wrong by a 1 cm or 5 deg
// object-mount error or by a 50 ms latency error during motion are flagged. The rates are over the
// scenario's four objects (oil bottle, funnel, engine block, table). A wrong label whose error lies mostly
// in directions the depth does not constrain (a table slid in its own plane: less than half the error's
// size left in the judged directions) is counted apart, as "hidden", as the accuracy sweep does.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <tuple>

#include "session_fixture.h"
#include "pipeline/demo.h"
#include "tests/pipeline/label_run_testing.h"
#include "pipeline/record_stage.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

/// Labels whose pose differs from the correct label by at least this much count as wrong: the size of
/// the injected mount errors (less a rounding margin), twice the verdict's accept bounds (5 mm, 3 deg),
/// so the validator's own estimate noise cannot make a wrong label look right. For the funnel the
/// difference is taken modulo its axis of revolution: a turn about it changes neither surface nor mask.
constexpr double kWrongPositionM = 0.00999;
constexpr double kWrongRotationDeg = 4.999;
/// Labels closer than this to the correct label count as correct in the latency case.
constexpr double kCorrectPositionM = 0.002;
constexpr double kCorrectRotationDeg = 1.0;

class SimSessionCheckTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(testing::FreshTempDir("validate_sim"));
    sim::Scenario scenario = sim::DefaultScenario();
    scenario.options.start_s = 3.4;  // mid-carry: the bottle moves at ~0.2 m/s while the head pans
    scenario.options.frame_count = kFrames;
    sim::RecordOptions record;
    record.out_dir = *dir_ / "session";
    record.threads = 2;
    record.context.platform = EglPlatform::kSurfaceless;
    record_ = new sim::RecordResult(pipeline::RecordSimulatedSession(scenario, nullptr, record).record);
    session_ = new SessionReader(SessionReader::Open(record_->session_dir));
    objects_ = new std::vector<ValidationObject>(pipeline::ValidationObjectsOf(pipeline::BuiltInLibraryOf(*record_)));
    Label(record_->truth.true_calibration, Labels());
  }
  static void TearDownTestSuite() {
    delete objects_;
    delete session_;
    delete record_;
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path Labels() { return *dir_ / "labels"; }
  static void Label(const sim::RigCalibration& calibration, const fs::path& out) {
    pipeline::DemoOptions options;
    options.out_dir = *dir_;
    options.threads = 2;
    options.context.platform = EglPlatform::kSurfaceless;
    pipeline::LabelRecording(*record_, calibration, out, options);
  }
  static SessionValidation Check(const fs::path& labels) {
    SessionCheckOptions o;
    o.labels_dir = labels;
    o.threads = 2;
    return CheckSession(*session_, *objects_, o);
  }
  static constexpr int kFrames = 16;
  static fs::path* dir_;
  static sim::RecordResult* record_;
  static SessionReader* session_;
  static std::vector<ValidationObject>* objects_;
};
fs::path* SimSessionCheckTest::dir_ = nullptr;
sim::RecordResult* SimSessionCheckTest::record_ = nullptr;
SessionReader* SimSessionCheckTest::session_ = nullptr;
std::vector<ValidationObject>* SimSessionCheckTest::objects_ = nullptr;

/// How far a label is from the correct label of the same record (modulo the object's symmetry): in all
/// directions, and in those the record's analysis judged.
struct LabelError {
  double m = 0.0, deg = 0.0;
  ObservedDifference judged;
  /// Wrong (at least the injected error's size) but mostly in directions the depth does not constrain.
  bool Hidden() const { return judged.position_mm < 0.5e3 * kWrongPositionM && judged.rotation_deg < 0.5 * kWrongRotationDeg; }
};
LabelError LabelErrorOf(const RecordCheck& r, const Rigid3d& correct, const std::vector<ValidationObject>& objects) {
  Rigid3d label = r.T_camera_object_label;
  for (const ValidationObject& o : objects)
    if (o.id == r.object && o.symmetry) label = NearestSymmetricPose(label, correct, *o.symmetry);
  return {TranslationDistanceM(label, correct), RotationDistanceDeg(label, correct),
          ObservedPart(r.check.observability, correct, label)};
}

std::map<std::pair<int64_t, int>, Rigid3d> LabelsByRecord(const fs::path& labels) {
  std::map<std::pair<int64_t, int>, Rigid3d> out;
  for (const RecordCheck& r : ReadLabelRecords(labels).records) out[{r.index, r.instance}] = r.T_camera_object_label;
  return out;
}

void PrintNotAccepted(const SessionValidation& v) {
  for (const RecordCheck& r : v.records)
    if (r.check.verdict != Verdict::kAccept)
      std::printf("  not accepted: frame %lld %s: %s\n", static_cast<long long>(r.index), r.name.c_str(),
                  r.check.reason.c_str());
}

TEST_F(SimSessionCheckTest, CorrectLabelsMeetTheAccuracyTargetsAndMountErrorsAreFlagged) {
  const SessionValidation good = Check(Labels());
  const testing::Rates correct = testing::ComputeRates(good);
  std::printf("correct labels: %lld checked, accepted %.3f, success %.3f, median %.2f mm %.2f deg, %.1f s\n",
              static_cast<long long>(correct.checked), correct.accepted, correct.success,
              good.summary.position_error_mm.median, good.summary.rotation_angle_error_deg.median, good.summary.seconds);
  PrintNotAccepted(good);
  EXPECT_GE(correct.checked, 2 * kFrames);
  EXPECT_LE(correct.checked, 4 * kFrames);
  EXPECT_GE(correct.success, 0.98);
  EXPECT_LE(good.summary.position_error_mm.median, 3.0);
  EXPECT_LE(good.summary.rotation_angle_error_deg.median, 1.5);
  EXPECT_LE(correct.flagged, 0.05);

  std::vector<std::string> names;
  for (const ValidationObject& o : *objects_) names.push_back(o.name);
  for (const auto& [name, translation_m, angle_deg, seed] : {std::tuple{"1cm", 0.01, 0.0, 3u}, std::tuple{"5deg", 0.0, 5.0, 4u}}) {
    // Labelled with the mounts off, so that the masks are drawn at the wrong labels (a user's session).
    const fs::path labels = *dir_ / (std::string("labels_") + name);
    const sim::CalibrationErrors errors = testing::ObjectMountErrors(names, translation_m, angle_deg, seed);
    Label(sim::ApplyCalibrationErrors(record_->truth.true_calibration, errors), labels);
    const SessionValidation checked = Check(labels);
    const testing::Rates all = testing::ComputeRates(checked);
    const auto correct_labels = LabelsByRecord(Labels());
    int wrong = 0, wrong_flagged = 0, hidden = 0;
    for (const RecordCheck& r : checked.records) {
      if (IsBadInput(r.check.reason_code)) continue;
      const LabelError error = LabelErrorOf(r, correct_labels.at({r.index, r.instance}), *objects_);
      const double error_m = error.m, error_deg = error.deg;
      if (error_m < kWrongPositionM && error_deg < kWrongRotationDeg) continue;
      if (error.Hidden()) {
        std::printf("  hidden: frame %lld %s, %.1f mm %.1f deg off, %.1f mm %.1f deg of it judged (%d directions): %s\n",
                    static_cast<long long>(r.index), r.name.c_str(), 1e3 * error_m, error_deg, error.judged.position_mm,
                    error.judged.rotation_deg, r.check.observability.observable, ToString(r.check.verdict).data());
        ++hidden;
        continue;
      }
      ++wrong;
      wrong_flagged += r.check.verdict != Verdict::kAccept;
      if (r.check.verdict == Verdict::kAccept)
        std::printf("  wrong but accepted: frame %lld %s (%s), %.1f mm %.1f deg off; estimate differs %.1f mm %.1f "
                    "deg, %.1f mm %.1f deg where observable (%d directions); estimate vs correct label %.1f mm %.1f deg\n",
                    static_cast<long long>(r.index), r.name.c_str(), r.mode.c_str(), 1e3 * error_m, error_deg,
                    r.check.errors.position_mm, r.check.errors.rotation_angle_deg, r.check.observed.position_mm,
                    r.check.observed.rotation_deg, r.check.observability.observable,
                    ComputePoseErrors(r.check.T_camera_object_segicp, correct_labels.at({r.index, r.instance})).position_mm,
                    ComputePoseErrors(r.check.T_camera_object_segicp, correct_labels.at({r.index, r.instance})).rotation_angle_deg);
    }
    std::printf("%s mount error: %lld checked, flagged %.3f; %d wrong modulo symmetry, %d of them flagged, %d more hidden\n",
                name, static_cast<long long>(all.checked), all.flagged, wrong, wrong_flagged, hidden);
    EXPECT_EQ(all.checked, correct.checked) << name;
    EXPECT_GE(wrong, correct.checked / 2) << name;
    EXPECT_GE(wrong_flagged, 0.95 * wrong) << name;
  }
}

TEST_F(SimSessionCheckTest, LabelsMadeWithALatencyErrorAreFlaggedWhereTheMotionMovesThem) {
  const fs::path late_labels = *dir_ / "labels_latency";
  sim::CalibrationErrors late;
  late.latency_ms = 50;
  Label(sim::ApplyCalibrationErrors(record_->truth.true_calibration, late), late_labels);
  // How wrong each late label is: against the correct label of the same frame and instance.
  const auto correct_labels = LabelsByRecord(Labels());
  const SessionValidation checked = Check(late_labels);
  int wrong = 0, wrong_flagged = 0, hidden = 0, right = 0, right_flagged = 0;
  for (const RecordCheck& r : checked.records) {
    if (IsBadInput(r.check.reason_code)) continue;
    const auto it = correct_labels.find({r.index, r.instance});
    ASSERT_NE(it, correct_labels.end()) << "frame " << r.index << " instance " << r.instance;
    const LabelError error = LabelErrorOf(r, it->second, *objects_);
    const double error_m = error.m, error_deg = error.deg;
    const bool flagged = r.check.verdict != Verdict::kAccept;
    if (error_m >= kWrongPositionM || error_deg >= kWrongRotationDeg) {
      if (error.Hidden()) {
        ++hidden;
        continue;
      }
      ++wrong;
      wrong_flagged += flagged;
      if (!flagged)
        std::printf("  wrong but accepted: frame %lld %s, %.1f mm %.1f deg off\n", static_cast<long long>(r.index),
                    r.name.c_str(), 1e3 * error_m, error_deg);
    } else if (error_m < kCorrectPositionM && error_deg < kCorrectRotationDeg) {
      ++right;
      right_flagged += flagged;
    }
  }
  std::printf("50 ms latency: %d wrong labels (>= 1 cm or 5 deg), %d flagged, %d more hidden; %d still correct, %d flagged\n",
              wrong, wrong_flagged, hidden, right, right_flagged);
  ASSERT_GE(wrong, kFrames / 3) << "the piece should be mid-carry";
  EXPECT_GE(wrong_flagged, 0.95 * wrong);
  EXPECT_LE(right_flagged, 0.05 * right + 1e-9);
}

}  // namespace
}  // namespace mocap
