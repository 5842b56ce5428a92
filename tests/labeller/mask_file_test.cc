// The packed mask file (one 8-bit PNG per object, three masks as bits, cropped to the amodal box) and the
// rendered-depth OpenEXR writer: both must give back exactly what was written.
#include "label/mask_file.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/check.h"
#include "label/depth_exr.h"
#include "labeller_test_util.h"
#include "session/image_io.h"

namespace mocap {
namespace {

/// Masks over a 12x9 rect at (30, 20) of an object whose amodal silhouette is a disc; visible_model is
/// its left part; visible_measured its top part, which includes pixels hidden in the model z-buffer
/// (the masks are not nested).
ObjectMasks DiscMasks(bool with_measured) {
  ObjectMasks m;
  m.rect = {30, 20, 12, 9};
  const size_t n = 12 * 9;
  m.amodal.assign(n, 0);
  m.visible_model.assign(n, 0);
  if (with_measured) m.visible_measured.assign(n, 0);
  for (int v = 0; v < 9; ++v) {
    for (int u = 0; u < 12; ++u) {
      const size_t i = static_cast<size_t>(v) * 12 + u;
      if ((u - 6) * (u - 6) + (v - 4) * (v - 4) > 9) continue;
      m.amodal[i] = 1;
      m.visible_model[i] = u < 6;
      if (with_measured) m.visible_measured[i] = v < 4;
    }
  }
  return m;
}

void ExpectSameFullMasks(const ObjectMasks& a, const ObjectMasks& b) {
  const auto same = [&](const std::vector<uint8_t>& x, const std::vector<uint8_t>& y) {
    ASSERT_EQ(x.empty(), y.empty());
    if (x.empty()) return;
    EXPECT_EQ(ToFullImage(x, a.rect, 64, 48).data, ToFullImage(y, b.rect, 64, 48).data);
  };
  same(a.amodal, b.amodal);
  same(a.visible_model, b.visible_model);
  same(a.visible_measured, b.visible_measured);
}

TEST(MaskFile, ThreeMasksComeBackExactlyThroughThePng) {
  const auto dir = testing::FreshDir("mask_file");
  for (const bool with_measured : {true, false}) {
    const ObjectMasks masks = DiscMasks(with_measured);
    const PackedMasks packed = PackMasks(masks);
    // Cropped to the disc (radius 3 around (36, 24)), not the whole rect.
    EXPECT_EQ(packed.rect.x, 33);
    EXPECT_EQ(packed.rect.y, 21);
    EXPECT_EQ(packed.rect.width, 7);
    EXPECT_EQ(packed.rect.height, 7);
    WriteLabelPng(dir / "m.png", packed.bits);
    const ObjectMasks back = ReadMaskFile(dir / "m.png", packed.rect, with_measured);
    ExpectSameFullMasks(masks, back);
    // A pixel visible by measured depth but hidden in the z-buffer keeps exactly that combination.
    if (with_measured) {
      EXPECT_TRUE(back.at(back.visible_measured, 37, 22));
      EXPECT_FALSE(back.at(back.visible_model, 37, 22));
    }
  }
  std::filesystem::remove_all(dir);
}

TEST(MaskFile, AFramesObjectsShareOneFile) {
  // Two objects and one outside the image: the file stacks the two crops, each readable by its row.
  const auto dir = testing::FreshDir("mask_file_stack");
  ObjectMasks wide;
  wide.rect = {5, 6, 20, 3};
  wide.amodal.assign(60, 1);
  wide.visible_model.assign(60, 0);
  for (size_t i = 0; i < 60; i += 7) wide.visible_model[i] = 1;
  const ObjectMasks disc = DiscMasks(false);
  ObjectMasks outside = disc;
  std::fill(outside.amodal.begin(), outside.amodal.end(), 0);
  std::fill(outside.visible_model.begin(), outside.visible_model.end(), 0);
  PackedMasks a = PackMasks(disc), none = PackMasks(outside), b = PackMasks(wide);
  const cv::Mat file = StackMasks({&a, &none, &b});
  EXPECT_EQ(file.cols, 20);
  EXPECT_EQ(file.rows, 7 + 3);
  EXPECT_EQ(a.file_row, 0);
  EXPECT_EQ(b.file_row, 7);
  WriteLabelPng(dir / "f.png", file);
  ExpectSameFullMasks(disc, ReadMaskFile(dir / "f.png", a.rect, false, a.file_row));
  ExpectSameFullMasks(wide, ReadMaskFile(dir / "f.png", b.rect, false, b.file_row));
  EXPECT_THROW(ReadMaskFile(dir / "f.png", b.rect, false, 8), InputError);  // rows beyond the file
  EXPECT_TRUE(StackMasks({&none}).empty());
  std::filesystem::remove_all(dir);
}

TEST(MaskFile, NoFileForAnObjectOutsideTheImage) {
  ObjectMasks masks;
  masks.rect = {0, 0, 4, 4};
  masks.amodal.assign(16, 0);
  masks.visible_model.assign(16, 0);
  const PackedMasks packed = PackMasks(masks);
  EXPECT_TRUE(packed.rect.empty());
  EXPECT_TRUE(packed.bits.empty());
}

TEST(MaskFile, RefusesFilesThatDoNotMatch) {
  const auto dir = testing::FreshDir("mask_file_bad");
  const PackedMasks packed = PackMasks(DiscMasks(true));
  WriteLabelPng(dir / "m.png", packed.bits);
  EXPECT_THROW(ReadMaskFile(dir / "m.png", {33, 21, 8, 7}, true), InputError);
  EXPECT_THROW(ReadMaskFile(dir / "missing.png", packed.rect, true), InputError);
  cv::Mat bad = packed.bits.clone();
  bad.at<uint8_t>(3, 3) = 255;  // a full-size 0/255 mask is not a packed one
  WriteLabelPng(dir / "bad.png", bad);
  try {
    ReadMaskFile(dir / "bad.png", packed.rect, true);
    ADD_FAILURE() << "a 0/255 mask was accepted as packed bits";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(RenderedDepthExr, EveryCodecIsLossless) {
  const auto dir = testing::FreshDir("depth_exr");
  DepthImage depth(64, 48, 0.0f);
  for (int v = 10; v < 30; ++v)
    for (int u = 5; u < 50; ++u) depth.at(u, v) = 0.7f + 1e-4f * static_cast<float>(u * v) + 1e-7f * static_cast<float>(u);
  for (const char* name : {"none", "rle", "zips", "zip", "piz"}) {
    const DepthCompression c = DepthCompressionFromString(name);
    EXPECT_STREQ(DepthCompressionName(c), name);
    WriteRenderedDepthExr(dir / "d.exr", depth, c);
    const DepthImage back = ReadDepth(dir / "d.exr", 1.0);
    EXPECT_EQ(back.data, depth.data) << name;
  }
  EXPECT_THROW(DepthCompressionFromString("half"), InputError);
  EXPECT_THROW(WriteRenderedDepthExr(dir / "no" / "such" / "d.exr", depth, DepthCompression::kRle), InputError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mocap
