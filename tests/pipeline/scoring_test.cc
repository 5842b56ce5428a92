// Scoring of a label run against a simulated truth, on hand-made files: pose errors, mask IoU from the
// instance images, records without a pose, and errors for missing truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "session/manifest.h"
#include "pipeline/label_run.h"
#include "pipeline/scoring.h"

namespace mocap::pipeline {
namespace {

namespace fs = std::filesystem;

/// 64x48 instance image with value `id` over [x0, x1) x [y0, y1).
void WriteIds(const fs::path& path, int id, int x0, int x1, int y0, int y1) {
  cv::Mat ids(48, 64, CV_16UC1, cv::Scalar(0));
  ids(cv::Rect(x0, y0, x1 - x0, y1 - y0)).setTo(id);
  fs::create_directories(path.parent_path());
  ASSERT_TRUE(cv::imwrite(path.string(), ids));
}

class ScoringTest : public testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: ctest runs the cases of this fixture in parallel.
    root_ = fs::path(testing::TempDir()) / (std::string("mocap_scoring_") +
                                            testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    const Rigid3d truth = Rigid3d::FromRvec({0, 0, 0}, {0.1, 0.0, 1.0});
    fs::create_directories(root_ / "truth");
    std::ofstream poses(root_ / "truth" / "poses.jsonl");
    for (int f = 0; f < 2; ++f)
      poses << nlohmann::json{{"index", f}, {"objects", {{{"name", "box"}, {"id", 7}, {"T_color_mesh", ToJson(truth)}}}}}.dump() << "\n";
    poses.close();
    WriteIds(root_ / "truth" / "instance" / "000000.png", 7, 10, 30, 10, 30);  // 400 px
    WriteIds(root_ / "truth" / "instance" / "000001.png", 7, 10, 30, 10, 30);
    WriteIds(root_ / "labels" / "cam" / "instance" / "000000.png", 2, 20, 40, 10, 30);  // overlaps 200 px
    WriteIds(root_ / "labels" / "cam" / "instance" / "000001.png", 2, 10, 30, 10, 30);
  }
  void WriteLabels(const std::vector<LabelRecord>& records) {
    std::ofstream labels(root_ / "labels" / "labels.jsonl");
    for (const auto& r : records) labels << ToJson(r).dump() << "\n";
    std::ofstream(root_ / "labels" / "label_manifest.json") << "{\"complete\": true}\n";
  }
  // `index`: the record's place in the labelled session; `frame`: the simulated frame it shows.
  static LabelRecord Record(int index, const std::string& name, std::vector<double> rvec, std::vector<double> t_m,
                            int frame = -1) {
    LabelRecord r = WithoutPose(index, name, 2, frame);
    r.has_pose = true;
    r.rvec = {rvec[0], rvec[1], rvec[2]};
    r.t_m = {t_m[0], t_m[1], t_m[2]};
    return r;
  }
  static LabelRecord WithoutPose(int index, const std::string& name, int instance, int frame = -1) {
    LabelRecord r;
    r.camera = "cam", r.index = index, r.frame = frame < 0 ? index : frame, r.name = name, r.object_class = name;
    r.instance = instance, r.object = 7, r.body = name + "_body";
    return r;
  }
  fs::path root_;
};

TEST_F(ScoringTest, PoseErrorsAndMaskIouAgainstTheTruth) {
  const double one_deg = M_PI / 180;
  WriteLabels({Record(0, "box", {0, 0, 0}, {0.103, 0.004, 1.0}),  // 5 mm off, exact rotation
               Record(1, "box", {0, one_deg, 0}, {0.1, 0.0, 1.0}),  // exact position, 1 degree off
               WithoutPose(1, "box", 3)});
  const LabelScores s = ScoreLabels(root_ / "labels", root_ / "truth");
  EXPECT_EQ(s.records, 3);
  EXPECT_EQ(s.records_without_pose, 1);
  EXPECT_EQ(s.frames, 2);
  ASSERT_EQ(s.per_record.size(), 2u);
  EXPECT_NEAR(s.per_record[0].err_mm, 5.0, 1e-9);
  EXPECT_NEAR(s.per_record[0].err_deg, 0.0, 1e-9);
  EXPECT_NEAR(s.per_record[1].err_deg, 1.0, 1e-9);
  EXPECT_NEAR(s.per_record[0].iou, 200.0 / 600.0, 1e-12);
  EXPECT_NEAR(s.per_record[1].iou, 1.0, 1e-12);
  EXPECT_NEAR(s.mask_iou_mean, (1.0 / 3 + 1.0) / 2, 1e-12);
  EXPECT_NEAR(s.pose_err_mm_median, 2.5, 1e-9);
}

TEST_F(ScoringTest, RecordsAreMatchedToTheTruthBySimulatedFrameNotBySessionPlace) {
  // A recording that dropped simulated frame 0: its first record (index 0) shows frame 1. Frame 1's
  // truth box sits at x 10-30, the label image at index 0 at x 20-40: IoU 1/3 when matched by frame.
  const double one_deg = M_PI / 180;
  WriteLabels({Record(0, "box", {0, one_deg, 0}, {0.1, 0.0, 1.0}, /*frame=*/1)});
  WriteIds(root_ / "truth" / "instance" / "000000.png", 7, 0, 0, 0, 0);  // frame 0's truth: nothing visible
  const LabelScores s = ScoreLabels(root_ / "labels", root_ / "truth");
  ASSERT_EQ(s.per_record.size(), 1u);
  EXPECT_EQ(s.per_record[0].index, 1);
  EXPECT_NEAR(s.per_record[0].iou, 200.0 / 600.0, 1e-12) << "label image by session place, truth by frame";
  EXPECT_NEAR(s.per_record[0].err_deg, 1.0, 1e-9);
}

TEST_F(ScoringTest, RecordWithoutTruthIsAnError) {
  WriteLabels({Record(0, "funnel", {0, 0, 0}, {0, 0, 1})});
  EXPECT_THROW(ScoreLabels(root_ / "labels", root_ / "truth"), InputError);
  fs::remove(root_ / "truth" / "poses.jsonl");
  EXPECT_THROW(ScoreLabels(root_ / "labels", root_ / "truth"), InputError);
}

TEST_F(ScoringTest, ACutOrColourInstanceImageIsAnErrorNamingIt) {
  WriteLabels({Record(0, "box", {0, 0, 0}, {0.1, 0.0, 1.0})});
  const fs::path png = root_ / "labels" / "cam" / "instance" / "000000.png";
  const auto expect_error_naming = [&](const std::string& what) {
    try {
      ScoreLabels(root_ / "labels", root_ / "truth");
      FAIL() << "no error for " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(png.string()), std::string::npos) << what << ": " << e.what();
    }
  };
  const uintmax_t size = fs::file_size(png);
  fs::resize_file(png, size / 2);
  expect_error_naming("a cut PNG");
  ASSERT_TRUE(cv::imwrite(png.string(), cv::Mat(48, 64, CV_8UC3, cv::Scalar(1, 2, 3))));
  expect_error_naming("a colour PNG");
}

TEST(Scoring, PercentileInterpolatesBetweenOrderStatistics) {
  EXPECT_EQ(Percentile({}, 50), 0);
  EXPECT_DOUBLE_EQ(Percentile({3, 1, 2, 4}, 50), 2.5);
  EXPECT_DOUBLE_EQ(Percentile({3, 1, 2, 4}, 0), 1);
  EXPECT_DOUBLE_EQ(Percentile({3, 1, 2, 4}, 100), 4);
}

}  // namespace
}  // namespace mocap::pipeline
