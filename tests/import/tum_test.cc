#include "session/import/tum.h"

#include <algorithm>
#include <set>
#include <sstream>
#include <tuple>

#include "test_util.h"

namespace mocap::import {
namespace {

using ::testing::HasSubstr;
using testing::InputErrorOf;
using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

// associate.py, literally: every pair under max_difference as (diff, a, b) in doubles, sorted, greedy.
std::set<std::pair<double, double>> ReferenceAssociate(const TumImageList& first, const TumImageList& second) {
  std::vector<std::tuple<double, double, double>> potential;
  for (const auto& a : first.entries)
    for (const auto& b : second.entries) {
      const double ta = std::stod(a.stamp_text), tb = std::stod(b.stamp_text);
      if (std::abs(ta - tb) < 0.02) potential.emplace_back(std::abs(ta - tb), ta, tb);
    }
  std::sort(potential.begin(), potential.end());
  std::set<double> used_a, used_b;
  std::set<std::pair<double, double>> matches;
  for (const auto& [diff, a, b] : potential)
    if (!used_a.contains(a) && !used_b.contains(b)) {
      used_a.insert(a);
      used_b.insert(b);
      matches.emplace(a, b);
    }
  return matches;
}

std::set<std::pair<double, double>> AsStampPairs(const TumImageList& first, const TumImageList& second,
                                                 const std::vector<TumAssociation>& pairs) {
  std::set<std::pair<double, double>> out;
  for (const auto& p : pairs)
    out.emplace(std::stod(first.entries[p.first].stamp_text), std::stod(second.entries[p.second].stamp_text));
  return out;
}

TEST(Tum, ReadsFr1DeskListsGroundTruthAndPresence) {
  const auto seq = ReadTumSequence(RealData("tum_fr1_desk_9frames"));
  EXPECT_EQ(seq.rgb.entries.size(), 613u);
  EXPECT_EQ(seq.depth.entries.size(), 595u);
  EXPECT_EQ(seq.groundtruth.samples.size(), 2335u);
  EXPECT_EQ(seq.rgb.missing_files(), 613 - 9);
  EXPECT_EQ(seq.depth.missing_files(), 595 - 9);
  EXPECT_EQ(seq.rgb.bag_name, "rgbd_dataset_freiburg1_desk.bag");
  EXPECT_EQ(TumPresetFromBagName(seq.rgb.bag_name), TumCameraPreset::kFreiburg1);
  EXPECT_EQ(seq.groundtruth.duplicate_stamps, 0);
  // First ground-truth line: 1305031449.7996 1.2334 -0.0113 1.6941 0.7907 0.4393 -0.1770 -0.3879 (qx qy qz qw).
  const auto& first = seq.groundtruth.samples.front();
  EXPECT_EQ(first.stamp_ns, 1305031449799600000);
  EXPECT_NEAR(first.pose.translation().z(), 1.6941, 1e-12);
  const Eigen::Quaterniond q_file(-0.3879, 0.7907, 0.4393, -0.1770);
  EXPECT_LT(first.pose.rotation().angularDistance(q_file.normalized()), 1e-9);
}

TEST(Tum, AssociationMatchesAssociatePyAndTheShippedPairs) {
  const auto seq = ReadTumSequence(RealData("tum_fr1_desk_9frames"));
  EXPECT_EQ(AsStampPairs(seq.rgb, seq.depth, seq.rgb_depth), ReferenceAssociate(seq.rgb, seq.depth));
  // associate.txt (written by TUM's script) pairs the first two present images.
  std::istringstream shipped(ReadAll(RealData("tum_fr1_desk_9frames/associate.txt")));
  std::string rgb_stamp, rgb_file, depth_stamp, depth_file;
  int checked = 0;
  while (shipped >> rgb_stamp >> rgb_file >> depth_stamp >> depth_file) {
    const auto it = std::find_if(seq.rgb_depth.begin(), seq.rgb_depth.end(),
                                 [&](const auto& p) { return seq.rgb.entries[p.first].stamp_text == rgb_stamp; });
    ASSERT_NE(it, seq.rgb_depth.end());
    EXPECT_EQ(seq.depth.entries[it->second].stamp_text, depth_stamp);
    ++checked;
  }
  EXPECT_EQ(checked, 2);
  // Every present colour image has its present depth image.
  int present_pairs = 0;
  for (const auto& p : seq.rgb_depth) present_pairs += seq.rgb.entries[p.first].exists && seq.depth.entries[p.second].exists;
  EXPECT_EQ(present_pairs, 9);
}

TEST(Tum, ToleratesHeaderLineThatLostItsHash) {
  const auto dir = RealData("tum_fr1_xyz_index");
  const auto rgb = ReadTumImageList(dir / "rgb.txt", dir);
  const auto depth = ReadTumImageList(dir / "depth.txt", dir);
  EXPECT_EQ(rgb.entries.size(), 798u);
  EXPECT_EQ(depth.entries.size(), 798u);
  EXPECT_EQ(rgb.header_lines_without_hash, std::vector<int>{3});
  EXPECT_EQ(rgb.missing_files(), 798);
  std::vector<int64_t> a, b;
  for (const auto& e : rgb.entries) a.push_back(e.stamp_ns);
  for (const auto& e : depth.entries) b.push_back(e.stamp_ns);
  const auto pairs = AssociateTum(a, b);
  EXPECT_EQ(AsStampPairs(rgb, depth, pairs), ReferenceAssociate(rgb, depth));
  for (const auto& p : pairs) EXPECT_LT(p.difference_ns, 20'000'000);
}

TEST(Tum, Fr2DeskHasTheDuplicatedStampAndSixLongGaps) {
  const auto gt = ReadTumGroundTruth(RealData("tum_groundtruth_evo/fr2_desk_groundtruth.txt"));
  EXPECT_EQ(gt.samples.size(), 20957u);
  EXPECT_EQ(gt.duplicate_stamps, 1);
  int long_gaps = 0;
  for (size_t i = 1; i < gt.samples.size(); ++i) long_gaps += gt.samples[i].stamp_ns - gt.samples[i - 1].stamp_ns > 500'000'000;
  EXPECT_EQ(long_gaps, 6);
}

TEST(Tum, PublishedCameraModels) {
  const auto fr1 = TumCamera(TumCameraPreset::kFreiburg1);
  EXPECT_EQ(fr1.fx, 517.3);
  EXPECT_EQ(fr1.cy, 255.3);
  EXPECT_EQ(fr1.dist[4], 1.1633);
  const auto ros = TumCamera(TumCameraPreset::kRosDefault);
  EXPECT_EQ(ros.cx, 319.5);
  EXPECT_FALSE(ros.has_distortion());
  EXPECT_EQ(TumPresetFromName("fr3"), TumCameraPreset::kFreiburg3);
  EXPECT_THAT(InputErrorOf([] { TumPresetFromName("fr9"); }), HasSubstr("unknown camera preset"));
}

TEST(Tum, BadInputNamesFileAndLine) {
  ScratchDir dir;
  const auto gt_bad_number = dir.Write("a.txt", "# c\n1.0 0 0 0 0 0 0 1\n2.0 0 0 x 0 0 0 1\n");
  EXPECT_THAT(InputErrorOf([&] { ReadTumGroundTruth(gt_bad_number); }), HasSubstr("a.txt:3: 'x' is not a number"));
  const auto gt_missing_column = dir.Write("b.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  EXPECT_THAT(InputErrorOf([&] { ReadTumGroundTruth(gt_missing_column); }), HasSubstr("b.txt:2: expected"));
  const auto gt_wxyz = dir.Write("c.txt", "1.0 0 0 0 1 0 0 1\n");  // not a unit quaternion
  EXPECT_THAT(InputErrorOf([&] { ReadTumGroundTruth(gt_wxyz); }), HasSubstr("c.txt:1: quaternion"));
  const auto gt_backwards = dir.Write("d.txt", "2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  EXPECT_THAT(InputErrorOf([&] { ReadTumGroundTruth(gt_backwards); }), HasSubstr("d.txt:2: timestamps go backwards"));
  const auto list_mid_header = dir.Write("rgb.txt", "1.0 rgb/1.png\ntimestamp filename\n");
  EXPECT_THAT(InputErrorOf([&] { ReadTumImageList(list_mid_header, dir.path()); }), HasSubstr("rgb.txt:2:"));
  const auto list_three_fields = dir.Write("depth.txt", "1.0 depth/1.png extra\n");
  EXPECT_THAT(InputErrorOf([&] { ReadTumImageList(list_three_fields, dir.path()); }), HasSubstr("depth.txt:1: expected"));
  EXPECT_THAT(InputErrorOf([&] { ReadTumSequence(dir.path() / "none"); }), HasSubstr("not a folder"));
}

}  // namespace
}  // namespace mocap::import
