#include "session/import/plus_mha.h"

#include <algorithm>

#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using testing::InputErrorOf;
using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

const PlusTransformTrack& Track(const PlusSequence& seq, const std::string& name) {
  auto it = std::find_if(seq.transforms.begin(), seq.transforms.end(), [&](const auto& t) { return t.name == name; });
  MOCAP_CHECK(it != seq.transforms.end(), "no track ", name);
  return *it;
}

TEST(PlusMha, AllThreeRealLogsImport) {
  const auto ras = ReadPlusSequence(RealData("plus_ndi_tracking/ReferenceToRASCalibration.igs.mha"));
  const auto interp = ReadPlusSequence(RealData("plus_ndi_tracking/TransformInterpolationTest.igs.mha"));
  const auto tank = ReadPlusSequence(RealData("plus_ndi_tracking/WaterTankBottomTranslationTrackerBuffer-trimmed.igs.mha"));
  EXPECT_EQ(ras.frames.size(), 93u);
  EXPECT_EQ(interp.frames.size(), 500u);
  EXPECT_EQ(tank.frames.size(), 801u);
  auto names = [](const PlusSequence& s) {
    std::vector<std::string> out;
    for (const auto& t : s.transforms) out.push_back(t.name);
    return out;
  };
  EXPECT_THAT(names(ras), ElementsAre("ReferenceToTracker", "StylusToTracker"));
  EXPECT_THAT(names(interp), ElementsAre("ProbeToTracker", "ReferenceToTracker"));
  EXPECT_THAT(names(tank), ElementsAre("ProbeToTracker", "ReferenceToTracker", "StylusToTracker"));
  EXPECT_EQ(Track(tank, "StylusToTracker").from_frame, "Stylus");
  EXPECT_EQ(Track(tank, "StylusToTracker").to_frame, "Tracker");
  // A 16-number field without the <From>To<To>Transform name is listed, not imported.
  EXPECT_THAT(interp.ignored_fields, ElementsAre("Stylus"));
  // Rates from SOURCE.txt: about 15, 50 and 39 Hz.
  auto rate_hz = [](const PlusSequence& s) {
    return static_cast<double>(s.frames.size() - 1) * 1e9 / static_cast<double>(s.frames.back().stamp_ns - s.frames.front().stamp_ns);
  };
  EXPECT_NEAR(rate_hz(ras), 15.0, 1.5);
  EXPECT_NEAR(rate_hz(interp), 50.0, 5.0);
  EXPECT_NEAR(rate_hz(tank), 39.0, 4.0);
}

TEST(PlusMha, InvalidFrameIsMissingAndKeepsItsStatusText) {
  const auto seq = ReadPlusSequence(RealData("plus_ndi_tracking/TransformInterpolationTest.igs.mha"));
  const auto& probe = Track(seq, "ProbeToTracker");
  ASSERT_EQ(probe.samples.size(), 500u);
  int invalid = 0;
  for (size_t i = 0; i < probe.samples.size(); ++i) {
    if (probe.source_status[i] != "INVALID") continue;
    ++invalid;
    EXPECT_EQ(i, 7u);  // Seq_Frame0007_ProbeToTrackerTransformStatus = INVALID
    EXPECT_EQ(probe.samples[i].status, PoseStatus::kMissing);
    EXPECT_EQ(seq.frames[i].frame_number, 17);
  }
  EXPECT_EQ(invalid, 1);
  // Reference has no status field: its samples are valid.
  for (const auto& s : Track(seq, "ReferenceToTracker").samples) EXPECT_EQ(s.status, PoseStatus::kValid);
}

TEST(PlusMha, ConvertsMillimetresAndRowMajorMatrices) {
  const auto seq = ReadPlusSequence(RealData("plus_ndi_tracking/TransformInterpolationTest.igs.mha"));
  // Seq_Frame0000_ProbeToTrackerTransform = 0.97524 0.15126 0.161332 -300.321 -0.16592 0.98276 0.0815699
  //   -83.1709 -0.146213 -0.106318 0.983523 -1481.09 0 0 0 1
  const auto& T = Track(seq, "ProbeToTracker").samples[0].pose;
  EXPECT_NEAR(T.translation().x(), -0.300321, 1e-12);
  EXPECT_NEAR(T.translation().y(), -0.0831709, 1e-12);
  EXPECT_NEAR(T.translation().z(), -1.48109, 1e-12);
  Eigen::Matrix3d R_file;
  R_file << 0.97524, 0.15126, 0.161332, -0.16592, 0.98276, 0.0815699, -0.146213, -0.106318, 0.983523;
  EXPECT_LT((T.rotation_matrix() - R_file).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_EQ(seq.frames[0].stamp_ns, 1898165100000000);
  EXPECT_EQ(seq.frames[1].unfiltered_stamp_ns, 1898165121000000);
  EXPECT_EQ(seq.frames[0].frame_number, 3);
}

TEST(PlusMha, TruncatedAndCorruptFilesAreRefused) {
  ScratchDir dir;
  const std::string full = ReadAll(RealData("plus_ndi_tracking/ReferenceToRASCalibration.igs.mha"));
  // Cut in half at a line end: the header never reaches ElementDataFile.
  const auto cut = dir.Write("cut.mha", full.substr(0, full.rfind('\n', full.size() / 2) + 1));
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(cut); }), HasSubstr("cut.mha: header ends without 'ElementDataFile"));
  // Cut in the middle of a matrix: that line is reported.
  const size_t mid = full.find("Seq_Frame0050_StylusToTrackerTransform =");
  const auto torn = dir.Write("torn.mha", full.substr(0, mid + 60) + "\nElementDataFile = LOCAL\n");
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(torn); }), HasSubstr("torn.mha:"));
  // Drop frame 92 entirely but keep the end of the header: DimSize no longer matches.
  std::string dropped;
  std::istringstream lines(full);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("Seq_Frame0092_", 0) != 0) dropped += line + "\n";
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(dir.Write("drop.mha", dropped)); }),
              HasSubstr("DimSize announces 93 frames but the header holds 92"));
  const std::string header = "ObjectType = Image\nNDims = 3\nDimSize = 0 0 1\n";
  const auto fifteen = dir.Write("m.mha", header + "Seq_Frame0000_ToolToTrackerTransform = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0\n"
                                                     "Seq_Frame0000_Timestamp = 1.0\nElementDataFile = LOCAL\n");
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(fifteen); }), HasSubstr("m.mha:4: transform has 15 numbers"));
  const auto scaled = dir.Write("s.mha", header + "Seq_Frame0000_ToolToTrackerTransform = 2 0 0 0 0 2 0 0 0 0 2 0 0 0 0 1\n"
                                                  "Seq_Frame0000_Timestamp = 1.0\nElementDataFile = LOCAL\n");
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(scaled); }), HasSubstr("s.mha:4: not a rotation matrix"));
  const auto status = dir.Write("u.mha", header + "Seq_Frame0000_ToolToTrackerTransform = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
                                                  "Seq_Frame0000_ToolToTrackerTransformStatus = BROKEN\n"
                                                  "Seq_Frame0000_Timestamp = 1.0\nElementDataFile = LOCAL\n");
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(status); }), HasSubstr("u.mha:5: unknown transform status 'BROKEN'"));
  const auto no_stamp = dir.Write("t.mha", header + "Seq_Frame0000_ToolToTrackerTransform = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
                                                    "ElementDataFile = LOCAL\n");
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(no_stamp); }), HasSubstr("Seq_Frame0 has no Timestamp"));
  const auto payload = dir.Write("p.mha", "ObjectType = Image\nDimSize = 2 2 1\nElementType = MET_UCHAR\n"
                                          "Seq_Frame0000_Timestamp = 1.0\nElementDataFile = LOCAL\nab");
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(payload); }), HasSubstr("image data truncated: 4 bytes announced"));
  EXPECT_THAT(InputErrorOf([&] { ReadPlusSequence(dir.Write("x.mha", "hello\n")); }), HasSubstr("x.mha:1:"));
}

TEST(PlusMha, ToolStatusMapping) {
  EXPECT_EQ(PoseStatusFromPlus("OK"), PoseStatus::kValid);
  EXPECT_EQ(PoseStatusFromPlus("INVALID"), PoseStatus::kMissing);
  EXPECT_EQ(PoseStatusFromPlus("OUT_OF_VOLUME"), PoseStatus::kOutOfVolume);
  EXPECT_EQ(PoseStatusFromPlus("DISABLED"), PoseStatus::kDisabled);
  EXPECT_FALSE(PoseStatusFromPlus("ok").has_value());
}

}  // namespace
}  // namespace mocap::import
