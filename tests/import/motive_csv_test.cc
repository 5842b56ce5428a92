#include "session/import/motive_csv.h"

#include <sstream>

#include "session/import/text_parse.h"
#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::HasSubstr;
using testing::InputErrorOf;
using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

const std::string kTake = "optitrack_neon_calib/optitrack_take.csv";

std::vector<std::vector<std::string>> Cells(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::vector<std::string> row;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) row.push_back(cell);
    if (!line.empty() && line.back() == ',') row.push_back("");
    rows.push_back(row);
  }
  return rows;
}

std::string Join(const std::vector<std::vector<std::string>>& rows) {
  std::string out;
  for (const auto& row : rows) {
    for (size_t i = 0; i < row.size(); ++i) out += (i ? "," : "") + row[i];
    out += "\r\n";
  }
  return out;
}

TEST(MotiveCsv, ReadsTheRealTake) {
  const auto take = ReadMotiveCsv(RealData(kTake));
  EXPECT_EQ(take.info.at("Format Version"), "1.24");
  EXPECT_EQ(take.length_unit_m, 1.0);
  ASSERT_EQ(take.frame_ids.size(), 241u);
  EXPECT_EQ(take.stamps_ns.back(), 2'000'000'000);
  ASSERT_EQ(take.rigid_bodies.size(), 2u);
  EXPECT_EQ(take.rigid_bodies[0].name, "NEON_DISPLAY_CALIB");
  EXPECT_EQ(take.rigid_bodies[1].name, "NEON_FRAME");
  EXPECT_EQ(take.rigid_bodies[0].id, "1CA3D4AB50DD11F0C526703E4ADC5193");
  EXPECT_EQ(take.markers.size(), 20u + 6u + 27u);  // rigid-body markers + labelled/unlabelled markers
  EXPECT_TRUE(take.ignored_columns.empty());
}

TEST(MotiveCsv, QuaternionOrderComesFromTheHeaderAndBlanksAreMissing) {
  const auto take = ReadMotiveCsv(RealData(kTake));
  const auto rows = Cells(ReadAll(RealData(kTake)));
  // Row 8 (frame 0): Rotation X Y Z W = 0.103280,-0.129924,0.036474,0.985456; Position 0.075586,0.512365,1.271660.
  const auto& first = take.rigid_bodies[0].samples[0];
  ASSERT_EQ(first.status, PoseStatus::kValid);
  const Eigen::Quaterniond q_file(0.985456, 0.103280, -0.129924, 0.036474);
  EXPECT_LT(first.pose.rotation().angularDistance(q_file.normalized()), 1e-9);
  EXPECT_NEAR(first.pose.translation().y(), 0.512365, 1e-12);
  // Missing samples are exactly the rows whose rigid-body cells are blank.
  for (size_t body = 0; body < 2; ++body) {
    const size_t column = body == 0 ? 2 : 69;
    int blank = 0, missing = 0;
    for (size_t r = 7; r < rows.size(); ++r) blank += rows[r][column].empty();
    for (const auto& s : take.rigid_bodies[body].samples) missing += s.status == PoseStatus::kMissing;
    EXPECT_EQ(missing, blank) << take.rigid_bodies[body].name;
    EXPECT_GT(blank, 0);
  }
}

TEST(MotiveCsv, MatchesTheCalibratedCameraMountWithinTheTake) {
  // The two bodies are rigidly attached during the take: their relative pose must barely move.
  const auto take = ReadMotiveCsv(RealData(kTake));
  std::vector<Rigid3d> relative;
  for (size_t i = 0; i < take.stamps_ns.size(); ++i) {
    const auto& a = take.rigid_bodies[0].samples[i];
    const auto& b = take.rigid_bodies[1].samples[i];
    if (a.status == PoseStatus::kValid && b.status == PoseStatus::kValid) relative.push_back(a.pose.inverse() * b.pose);
  }
  ASSERT_GT(relative.size(), 200u);
  const Rigid3d mean = AveragePoses(relative);
  for (const auto& r : relative) {
    EXPECT_LT(TranslationDistanceM(r, mean), 0.002);
    EXPECT_LT(RotationDistanceDeg(r, mean), 0.5);
  }
}

TEST(MotiveCsv, MillimetreExportsAreConverted) {
  ScratchDir dir;
  auto rows = Cells(ReadAll(RealData(kTake)));
  for (size_t i = 0; i + 1 < rows[0].size(); ++i)
    if (rows[0][i] == "Length Units") rows[0][i + 1] = "Millimeters";
  for (size_t r = 7; r < rows.size(); ++r)
    for (size_t c = 6; c < 9; ++c)
      if (!rows[r][c].empty()) rows[r][c] = std::to_string(std::stod(rows[r][c]) * 1000.0);
  const auto take = ReadMotiveCsv(dir.Write("mm.csv", Join(rows)));
  EXPECT_NEAR(take.rigid_bodies[0].samples[0].pose.translation().z(), 1.271660, 1e-9);
}

TEST(MotiveCsv, BadExportsNameFileAndLine) {
  ScratchDir dir;
  const auto rows = Cells(ReadAll(RealData(kTake)));
  auto without_column = rows;  // drop "Rotation W" of the first rigid body (column 6)
  for (size_t r = 2; r < without_column.size(); ++r) without_column[r].erase(without_column[r].begin() + 5);
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(dir.Write("a.csv", Join(without_column))); }),
              HasSubstr("a.csv:7: Rigid Body 'NEON_DISPLAY_CALIB' has no 'Rotation W' column"));
  auto euler = rows;
  for (size_t i = 0; i + 1 < euler[0].size(); ++i)
    if (euler[0][i] == "Rotation Type") euler[0][i + 1] = "XYZ";
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(dir.Write("b.csv", Join(euler))); }),
              HasSubstr("b.csv:1: Rotation Type is 'XYZ'"));
  auto text = rows;
  text[20][3] = "0.1.2";
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(dir.Write("c.csv", Join(text))); }), HasSubstr("c.csv:21 column 4"));
  const std::string full = Join(rows);
  const std::string truncated = full.substr(0, full.size() - 1000);
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(dir.Write("d.csv", truncated)); }), HasSubstr("(truncated file?)"));
  auto partial = rows;
  partial[30][4] = "";
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(dir.Write("e.csv", Join(partial))); }), HasSubstr("e.csv:31: rigid body"));
  auto units = rows;
  for (size_t i = 0; i + 1 < units[0].size(); ++i)
    if (units[0][i] == "Length Units") units[0][i + 1] = "Inches";
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(dir.Write("f.csv", Join(units))); }), HasSubstr("unknown Length Units"));
}

}  // namespace
}  // namespace mocap::import
