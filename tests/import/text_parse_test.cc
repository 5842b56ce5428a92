#include "session/import/text_parse.h"

#include <cmath>

#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::HasSubstr;
using testing::InputErrorOf;

TEST(TextParse, SecondsToNanosecondsIsExactForUnixTimes) {
  // 16 significant digits: a double would round these to about 0.2 us.
  EXPECT_EQ(NanosecondsFromSeconds("1305031453.359684", "x"), 1305031453359684000);
  EXPECT_EQ(NanosecondsFromSeconds("1311868229.5760", "x"), 1311868229576000000);
  EXPECT_EQ(NanosecondsFromSeconds("196.7208142857271", "x"), 196720814286);  // 10th digit rounds up
  EXPECT_EQ(NanosecondsFromSeconds("-0.5", "x"), -500000000);
  EXPECT_EQ(NanosecondsFromSeconds("7", "x"), 7000000000);
  EXPECT_EQ(NanosecondsFromSeconds(".25", "x"), 250000000);
  EXPECT_EQ(NanosecondsFromSeconds("1.5e-3", "x"), 1500000);
}

TEST(TextParse, BadNumbersNameTheirPlace) {
  EXPECT_THAT(InputErrorOf([] { NanosecondsFromSeconds("12.3.4", "f.txt:7"); }), HasSubstr("f.txt:7"));
  EXPECT_THAT(InputErrorOf([] { NanosecondsFromSeconds("", "f.txt:7"); }), HasSubstr("not a time"));
  EXPECT_THAT(InputErrorOf([] { ParseDouble("1.2x", "f.txt:3"); }), HasSubstr("f.txt:3: '1.2x' is not a number"));
  EXPECT_THAT(InputErrorOf([] { ParseDouble("nan", "f.txt:3"); }), HasSubstr("not a number"));
  EXPECT_THAT(InputErrorOf([] { ParseInt("4.0", "f.txt:2"); }), HasSubstr("not an integer"));
}

TEST(TextParse, SplitsKeepBlankCsvCellsAndStripCr) {
  const auto lines = SplitLines("a,,b\r\nc\n");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], "a,,b");
  const auto fields = SplitFields(lines[0], ',');
  ASSERT_EQ(fields.size(), 3u);
  EXPECT_EQ(fields[1], "");
  EXPECT_EQ(SplitWhitespace("  1 \t 2  ").size(), 2u);
}

TEST(TextParse, NearlyOrthonormalMatrixIsProjectedScaledOneRefused) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::Matrix3d rounded = (R * 1e5).array().round() / 1e5;  // five decimals, as files print them
  const Eigen::Quaterniond q = RotationFromNearlyOrthonormal(rounded, "x");
  EXPECT_LT(q.angularDistance(Eigen::Quaterniond(R)), 1e-4);
  EXPECT_THAT(InputErrorOf([&] { RotationFromNearlyOrthonormal(R * 1000.0, "m.txt:4"); }),
              HasSubstr("m.txt:4: not a rotation matrix"));
  EXPECT_THAT(InputErrorOf([&] { RotationFromNearlyOrthonormal(-R, "m"); }), HasSubstr("det"));
  EXPECT_THAT(InputErrorOf([] { QuaternionNearlyUnit(0.5, 0.1, 0.1, 1.2, "q"); }), HasSubstr("norm"));
}

}  // namespace
}  // namespace mocap::import
