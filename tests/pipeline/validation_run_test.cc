// validation.jsonl's record of one check (pipeline/validation_run.h): what the outline estimate did
// goes out and comes back; a malformed entry is an error naming the line and the field.
#include "pipeline/validation_run.h"

#include <gtest/gtest.h>

#include "core/check.h"

namespace mocap::pipeline {
namespace {

RecordCheck CheckedRecord() {
  RecordCheck r;
  r.camera = "kinect1", r.index = 12, r.stamp_ns = 400000000, r.object = 5, r.name = "table", r.instance = 5;
  r.mode = "tracking";
  r.T_camera_object_label = Rigid3d::FromRvec({0.1, 0.2, 0.3}, {0.1, -0.2, 1.4});
  LabelCheck& c = r.check;
  c.verdict = Verdict::kSuspect, c.reason_code = VerdictReason::kDiffers, c.reason = "SegICP differs";
  c.estimated = true;
  c.T_camera_object_segicp = Rigid3d::FromRvec({0.1, 0.2, 0.3}, {0.11, -0.2, 1.4});
  c.outline = {{3, false, 0.0074, 0.052, true}, {4, false, 0.0, 0.011, false}, {1, true, -0.0021, 0.31, true}};
  return r;
}

TEST(ValidationRecordJson, CarriesTheOutlineSteps) {
  const nlohmann::json j = ToJson(CheckedRecord());
  ASSERT_TRUE(j.contains("outline"));
  EXPECT_DOUBLE_EQ(j["outline"][0]["shift_mm"].get<double>(), 7.4);
  const RecordCheck back = RecordCheckFromJson(j, "validation.jsonl:1");
  ASSERT_EQ(back.check.outline.size(), 3u);
  EXPECT_EQ(back.check.outline[0].direction, 3);
  EXPECT_FALSE(back.check.outline[0].across_ray);
  EXPECT_FALSE(j["outline"][0].contains("across_ray"));  // written only for a move across the ray
  EXPECT_TRUE(back.check.outline[2].across_ray);
  EXPECT_EQ(back.check.outline[2].direction, 1);
  EXPECT_NEAR(back.check.outline[2].shift_m, -0.0021, 1e-12);
  EXPECT_NEAR(back.check.outline[0].shift_m, 0.0074, 1e-12);
  EXPECT_DOUBLE_EQ(back.check.outline[1].rise, 0.011);
  EXPECT_TRUE(back.check.outline[0].judged);
  EXPECT_FALSE(back.check.outline[1].judged);
  EXPECT_FALSE(j.contains("range_push_mm"));  // written only for a range-biased object's fitted push
}

TEST(ValidationRecordJson, CarriesARangeBiasedObjectsPush) {
  RecordCheck r = CheckedRecord();
  r.check.range_push_mm = 17.5;
  nlohmann::json j = ToJson(r);
  EXPECT_DOUBLE_EQ(RecordCheckFromJson(j, "validation.jsonl:7").check.range_push_mm, 17.5);
  j["range_push_mm"] = "far";
  EXPECT_THROW(RecordCheckFromJson(j, "validation.jsonl:7"), InputError);
}

TEST(ValidationRecordJson, AMalformedOutlineIsAnErrorNamingTheField) {
  nlohmann::json j = ToJson(CheckedRecord());
  j["outline"][1]["judged"] = "yes";
  try {
    RecordCheckFromJson(j, "validation.jsonl:7");
    FAIL() << "accepted a malformed outline step";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("validation.jsonl:7 outline[1]"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("judged"), std::string::npos) << e.what();
  }
  j["outline"][1]["judged"] = false;
  j["outline"][2]["across_ray"] = 1;
  EXPECT_THROW(RecordCheckFromJson(j, "validation.jsonl:7"), InputError);
  j["outline"] = 3;
  EXPECT_THROW(RecordCheckFromJson(j, "validation.jsonl:7"), InputError);
}

// A table top's record: its slides and spin unjudged. The judged directions come back for the calibration
// check, which measures only them (calibrate/calibration_check.h).
TEST(ValidationRecordJson, CarriesTheDirectionsTheDepthJudged) {
  RecordCheck r = CheckedRecord();
  Observability& o = r.check.observability;
  o.analysed = true;
  o.directions = Eigen::Matrix<double, 6, 6>::Identity();
  o.directions.topLeftCorner<2, 2>() << std::sqrt(0.5), -std::sqrt(0.5), std::sqrt(0.5), std::sqrt(0.5);
  o.judged = {true, false, true, false, false, true};
  o.observable = 3;
  o.center_object = {0.1, 0.2, -0.01};
  o.radius_m = 0.31;
  const nlohmann::json j = ToJson(r);
  ASSERT_EQ(j["judged_directions"].size(), 18u);
  const RecordCheck back = RecordCheckFromJson(j, "validation.jsonl:7");
  const Observability& b = back.check.observability;
  EXPECT_EQ(b.observable, 3);
  EXPECT_TRUE(b.judged[0] && b.judged[1] && b.judged[2] && !b.judged[3] && !b.judged[4] && !b.judged[5]);
  EXPECT_TRUE(b.directions.col(0).isApprox(o.directions.col(0)));
  EXPECT_TRUE(b.directions.col(1).isApprox(o.directions.col(2)));
  EXPECT_TRUE(b.directions.col(2).isApprox(o.directions.col(5)));
  EXPECT_TRUE((b.directions.transpose() * b.directions).isIdentity(1e-12));  // the basis completed
  EXPECT_TRUE(b.center_object.isApprox(o.center_object));
  EXPECT_DOUBLE_EQ(b.radius_m, 0.31);
  // A record with all six judged writes none.
  r.check.observability.judged.fill(true), r.check.observability.observable = 6;
  EXPECT_FALSE(ToJson(r).contains("judged_directions"));
  // Malformed: a count that does not match, a direction that is not a unit vector.
  nlohmann::json bad = j;
  bad["judged_directions"].erase(bad["judged_directions"].begin());
  EXPECT_THROW(RecordCheckFromJson(bad, "validation.jsonl:7"), InputError);
  bad = j;
  bad["judged_directions"][0] = 2.0;
  try {
    RecordCheckFromJson(bad, "validation.jsonl:7");
    FAIL() << "accepted a direction that is not a unit vector";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("validation.jsonl:7"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("judged_directions"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mocap::pipeline
