// The session-level check on LM-O scene 2 (real meshes, ground-truth poses, real occlusions; depth
// rendered at the ground truth with Kinect1 noise, since the scene ships no depth images): correct labels
// are accepted, 1 cm and 5 deg mount errors are flagged, and bad input gives verdicts with reasons.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <tuple>
#include <opencv2/imgcodecs.hpp>

#include "pipeline/session_wide.h"
#include "session_fixture.h"
#include "tests/pipeline/label_run_testing.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;

class SessionCheckTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(testing::FreshTempDir("validate_session"));
    scene_ = new testing::BopDepthScene(testing::MakeBopDepthScene(*dir_, {kNoDepthFrame}, 7));
    session_ = new SessionReader(SessionReader::Open(scene_->session));
  }
  static void TearDownTestSuite() {
    delete session_;
    delete scene_;
    fs::remove_all(*dir_);
    delete dir_;
  }
  static SessionCheckOptions Options(const fs::path& labels) {
    SessionCheckOptions o;
    o.labels_dir = labels;
    o.threads = 2;
    return o;
  }
  static constexpr int64_t kNoDepthFrame = 4;
  static fs::path* dir_;
  static testing::BopDepthScene* scene_;
  static SessionReader* session_;
};
fs::path* SessionCheckTest::dir_ = nullptr;
testing::BopDepthScene* SessionCheckTest::scene_ = nullptr;
SessionReader* SessionCheckTest::session_ = nullptr;

TEST_F(SessionCheckTest, AcceptsCorrectLabelsAndFlagsMountErrorsWithEitherCropSource) {
  const SessionValidation good = CheckSession(*session_, scene_->objects, Options(scene_->labels));
  const testing::Rates correct = testing::ComputeRates(good);
  std::printf("correct labels: %lld checked, accepted %.3f, success %.3f, median %.2f mm %.2f deg, %.1f s\n",
              static_cast<long long>(correct.checked), correct.accepted, correct.success,
              good.summary.position_error_mm.median, good.summary.rotation_angle_error_deg.median, good.summary.seconds);
  for (const RecordCheck& r : good.records)
    if (r.check.verdict != Verdict::kAccept && !IsBadInput(r.check.reason_code))
      std::printf("  not accepted: frame %lld %s: %s\n", static_cast<long long>(r.index), r.name.c_str(),
                  r.check.reason.c_str());
  EXPECT_GT(correct.checked, 50);
  EXPECT_GE(correct.accepted, 0.9);
  EXPECT_GE(correct.success, 0.98);
  EXPECT_LT(good.summary.position_error_mm.median, 3.0);
  EXPECT_LT(good.summary.rotation_angle_error_deg.median, 1.5);
  // The frame without depth: every record of it says so.
  for (const RecordCheck& r : good.records)
    if (r.index == kNoDepthFrame) {
      EXPECT_EQ(r.check.reason_code, VerdictReason::kNoDepth) << r.check.reason;
    }

  // The renderer-backed crops give the same verdicts.
  auto options = Options(scene_->labels);
  options.crops = CropBackend::kRenderer;
  const SessionValidation rendered = CheckSession(*session_, scene_->objects, options);
  const testing::Rates by_renderer = testing::ComputeRates(rendered);
  std::printf("renderer crops: accepted %.3f in %.1f s\n", by_renderer.accepted, rendered.summary.seconds);
  EXPECT_GE(by_renderer.accepted, 0.9);
  EXPECT_NEAR(by_renderer.accepted, correct.accepted, 0.06);

  for (const auto& [name, translation_m, angle_deg, seed] : {std::tuple{"1cm", 0.01, 0.0, 3u}, std::tuple{"5deg", 0.0, 5.0, 4u}}) {
    const fs::path labels = testing::LabelWithMountErrors(*dir_, name, translation_m, angle_deg, seed);
    SessionValidation checked = CheckSession(*session_, scene_->objects, Options(labels));
    const testing::Rates wrong = testing::ComputeRates(checked);
    std::printf("%s mount error: %lld checked, flagged %.3f\n", name, static_cast<long long>(wrong.checked), wrong.flagged);
    pipeline::FlagSessionWideErrors(checked, scene_->objects, {});
    std::printf("  with the session-wide step: flagged %.3f;", testing::ComputeRates(checked).flagged);
    if (checked.summary.session_wide)
      for (const std::string& finding : checked.summary.session_wide->findings) std::printf(" %s;", finding.c_str());
    std::printf("\n");
    for (const RecordCheck& r : checked.records)
      if (r.check.verdict == Verdict::kAccept)
        std::printf("  accepted: frame %lld %s: %s\n", static_cast<long long>(r.index), r.name.c_str(), r.check.reason.c_str());
    EXPECT_GE(wrong.flagged, 0.95) << name;
  }
}

TEST_F(SessionCheckTest, SequenceModeRunsOneTrackerPerInstance) {
  auto options = Options(scene_->labels);
  options.track = true;
  const SessionValidation v = CheckSession(*session_, scene_->objects, options);
  const testing::Rates rates = testing::ComputeRates(v);
  std::printf("sequence mode: %lld checked, accepted %.3f, success %.3f, %.1f s\n",
              static_cast<long long>(rates.checked), rates.accepted, rates.success, v.summary.seconds);
  EXPECT_GT(rates.checked, 50);
  for (const RecordCheck& r : v.records) {
    EXPECT_FALSE(r.mode.empty());
    if (r.index == kNoDepthFrame) {
      EXPECT_EQ(r.mode, "skipped");
    }
  }
  // No quality bound here: the 10 frames are far apart in time (BOP keeps every few images), so each
  // tracker re-acquires from the view sphere, unseeded and without the frame's occlusion filter
  // (docs/validation.md "Session check"). Sequence quality needs a continuous session.
  for (const RecordCheck& r : v.records)
    if (!IsBadInput(r.check.reason_code)) {
      EXPECT_TRUE(r.mode == "acquisition" || r.mode == "tracking") << r.mode;
    }
}

/// User masks: the label run's own instance PNGs with object ids, except for bad frames.
TEST_F(SessionCheckTest, UserMasksGiveSegmentationScoresAndBadInputGivesReasons) {
  const fs::path masks = *dir_ / "masks";
  fs::create_directories(masks);
  std::map<int64_t, std::map<int, int>> object_of_instance;
  for (const RecordCheck& r : ReadLabelRecords(scene_->labels).records) object_of_instance[r.index][r.instance] = r.object;
  for (const auto& [index, objects] : object_of_instance) {
    char stem[16];
    std::snprintf(stem, sizeof stem, "%06lld", static_cast<long long>(index));
    cv::Mat instance = cv::imread((scene_->labels / "bop" / "instance" / (std::string(stem) + ".png")).string(), cv::IMREAD_UNCHANGED);
    cv::Mat mask(instance.rows, instance.cols, CV_16UC1, cv::Scalar(0));
    for (int v = 0; v < instance.rows; ++v)
      for (int u = 0; u < instance.cols; ++u)
        if (auto it = objects.find(instance.at<uint16_t>(v, u)); it != objects.end()) mask.at<uint16_t>(v, u) = it->second;
    if (index == 1) mask = cv::Mat(instance.rows, instance.cols, CV_16UC1, cv::Scalar(0));  // empty
    if (index == 2) mask = cv::Mat(240, 320, CV_16UC1, cv::Scalar(1));                       // wrong size
    if (index == 3) {                                                                          // a few pixels only
      cv::Mat few(instance.rows, instance.cols, CV_16UC1, cv::Scalar(0));
      for (const auto& [inst, object] : objects) {
        const cv::Mat is = mask == object;
        std::vector<cv::Point> pixels;
        cv::findNonZero(is, pixels);
        for (size_t k = 0; k < std::min<size_t>(pixels.size(), 10); ++k) few.at<uint16_t>(pixels[k]) = object;
      }
      mask = few;
    }
    if (index == 5) continue;  // no mask file
    cv::imwrite((masks / (std::string(stem) + ".png")).string(), mask);
  }
  auto options = Options(scene_->labels);
  options.masks_dir = masks;
  const fs::path out = *dir_ / "V";
  const SessionValidation v = ValidateSession(*session_, scene_->objects, options, out);
  std::map<int64_t, std::set<std::string>> reasons;
  for (const RecordCheck& r : v.records) {
    reasons[r.index].insert(std::string(ToString(r.check.reason_code)));
    EXPECT_FALSE(r.check.reason.empty());
  }
  EXPECT_EQ(reasons[1], std::set<std::string>{"empty_mask"});
  EXPECT_EQ(reasons[2], std::set<std::string>{"mask_size_mismatch"});
  EXPECT_EQ(reasons[3], std::set<std::string>{"too_few_points"});
  EXPECT_EQ(reasons[kNoDepthFrame], std::set<std::string>{"no_depth"});
  EXPECT_EQ(reasons[5], std::set<std::string>{"unreadable_input"});
  ASSERT_TRUE(v.summary.has_segmentation);
  EXPECT_NEAR(v.summary.iou.median, 1.0, 1e-9);  // the unaltered frames are the label masks themselves
  EXPECT_LT(v.summary.iou.p95 - v.summary.iou.median, 1e-9);
  // The outputs: complete, with the summary fields the demo reads.
  std::ifstream summary_file(out / "validation.json");
  const auto summary = nlohmann::json::parse(summary_file);
  EXPECT_TRUE(summary["complete"].get<bool>());
  EXPECT_TRUE(summary.contains("segicp_success_rate"));
  EXPECT_EQ(summary["verdicts"]["accept"].get<int64_t>() + summary["verdicts"]["suspect"].get<int64_t>() +
                summary["verdicts"]["reject"].get<int64_t>(),
            static_cast<int64_t>(v.records.size()));
  std::ifstream html(out / "report.html");
  const std::string text((std::istreambuf_iterator<char>(html)), {});
  EXPECT_NE(text.find("<svg"), std::string::npos);
  EXPECT_NE(text.find("overlay/"), std::string::npos);
  EXPECT_FALSE(fs::exists(out.string() + ".partial"));
  // A folder that is not a validation output is never overwritten.
  EXPECT_THROW(ValidateSession(*session_, scene_->objects, options, scene_->labels), InputError);
}

TEST_F(SessionCheckTest, ASummaryWithNothingCheckedSaysWhy) {
  // --masks of the wrong size everywhere: no record can be checked. The summary must say so and why,
  // not report "SegICP success 0.0 %, position error median 0.00 mm" as if they were measurements.
  const fs::path masks = *dir_ / "small_masks";
  fs::create_directories(masks);
  for (int64_t index = 0; index < 16; ++index) {
    char stem[16];
    std::snprintf(stem, sizeof stem, "%06lld", static_cast<long long>(index));
    cv::imwrite((masks / (std::string(stem) + ".png")).string(), cv::Mat(240, 320, CV_16UC1, cv::Scalar(1)));
  }
  auto options = Options(scene_->labels);
  options.masks_dir = masks;
  const SessionValidation v = ValidateSession(*session_, scene_->objects, options, *dir_ / "V0");
  EXPECT_EQ(v.summary.records_checked, 0);
  EXPECT_NE(v.summary.nothing_checked_why.find("had unusable input"), std::string::npos) << v.summary.nothing_checked_why;
  std::ifstream summary_file(*dir_ / "V0" / "validation.json");
  const auto summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["nothing_checked_why"], v.summary.nothing_checked_why);
  // And a run where something was checked carries no such sentence.
  const SessionValidation ok = ValidateSession(*session_, scene_->objects, Options(scene_->labels), *dir_ / "V1");
  EXPECT_GT(ok.summary.records_checked, 0);
  EXPECT_TRUE(ok.summary.nothing_checked_why.empty());
}

}  // namespace
}  // namespace mocap
