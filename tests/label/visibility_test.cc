// The visible-mask rules (label/visibility.h, label/depth_holes.h) on hand-built frames: the render and
// the measured depth are drawn as characters, one per pixel, and so is the expected mask, so every case
// of a depth hole is checked pixel by pixel without a renderer.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/check.h"
#include "picture.h"
#include "label/object_labels.h"

namespace mocap {
namespace {

using test::CameraOf;
using test::Lines;
using test::Picture;

constexpr float kObjectA_m = 1.0f, kObjectB_m = 0.45f, kHand_m = 0.7f, kWall_m = 2.0f;

/// Every row of a picture has the first row's width.
void CheckWidths(const Picture& p) {
  for (const std::string& row : p) MOCAP_CHECK(row.size() == p[0].size(), "ragged picture row: ", row);
}

/// The render of `model`: 'A' object 1 at 1 m, 'B' object 2 at 0.45 m (in front of A where A's rectangle
/// is also drawn in `behind`), '.' nothing. `behind` marks with 'A' where A continues behind B.
RenderOutput RenderOf(const Picture& model, const Picture& behind) {
  CheckWidths(model);
  const int w = static_cast<int>(model[0].size()), h = static_cast<int>(model.size());
  RenderOutput r{LabelImage(w, h, 0), DepthImage(w, h, 0.0f), {}};
  for (const auto& [name, id, z] : {std::tuple{'A', uint16_t{1}, kObjectA_m}, std::tuple{'B', uint16_t{2}, kObjectB_m}}) {
    ObjectLayer layer{id, {0, 0, w, h}, std::vector<float>(static_cast<size_t>(w) * h, 0.0f)};
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u)
        if (model[v][u] == name || (name == 'A' && behind[v][u] == 'A')) {
          layer.depth_m[static_cast<size_t>(v) * w + u] = z, ++layer.px_count_all;
          if (model[v][u] == name) r.instance_ids.at(u, v) = id, r.depth_m.at(u, v) = z;
        }
    r.layers.push_back(std::move(layer));
  }
  return r;
}

/// Measured depth: 'o' object A's surface, 'b' object B's, 'h' an unmodelled hand at 0.7 m, 'w' the wall
/// at 2 m, '_' no depth.
DepthImage MeasuredOf(const Picture& p) {
  CheckWidths(p);
  DepthImage d(static_cast<int>(p[0].size()), static_cast<int>(p.size()), 0.0f);
  for (int v = 0; v < d.height; ++v)
    for (int u = 0; u < d.width; ++u) {
      const char c = p[v][u];
      d.at(u, v) = c == 'o' ? kObjectA_m : c == 'b' ? kObjectB_m : c == 'h' ? kHand_m : c == 'w' ? kWall_m : 0.0f;
      if (c != 'o' && c != 'b' && c != 'h' && c != 'w' && c != '_') ADD_FAILURE() << "bad depth character " << c;
    }
  return d;
}

/// The full-image visible mask of `labels` drawn as '#' (visible) and '.'.
Picture Draw(const ObjectLabels& labels, int w, int h) {
  Picture p(static_cast<size_t>(h), std::string(static_cast<size_t>(w), '.'));
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      if (labels.masks.at(labels.masks.visible_measured, u, v)) p[v][u] = '#';
  return p;
}

/// Object A's visible mask under `rule` for the model and measured depth drawn.
ObjectLabels LabelA(const Picture& model, const Picture& measured, VisibilityRule rule, const Picture& behind = {}) {
  const RenderOutput render = RenderOf(model, behind.empty() ? model : behind);
  const DepthImage depth = MeasuredOf(measured);
  VisibilityOptions options;
  options.rule = rule;
  return ComputeObjectLabels(render, CameraOf(model), &depth, options).at(0);
}

/// A's silhouette where `model` draws B in front of it: A continues behind B.
Picture ABehindB(const Picture& model) {
  Picture p = model;
  for (std::string& row : p)
    for (char& c : row) c = c == 'B' ? 'A' : c;
  return p;
}

/// `model` with its 'A' pixels as '#': all of A visible.
Picture AsMask(const Picture& model) {
  Picture p = model;
  for (std::string& row : p)
    for (char& c : row) c = c == 'A' ? '#' : '.';
  return p;
}

void ExpectMask(const ObjectLabels& labels, const Picture& expected) {
  const int w = static_cast<int>(expected[0].size()), h = static_cast<int>(expected.size());
  EXPECT_EQ(Lines(Draw(labels, w, h)), Lines(expected));
}

const Picture kObjectA = {
    "........................",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "..AAAAAAAAAAAAAAAAAAAA..",
    "........................",
};

TEST(VisibleMask, HoleOnAnUnmodelledOccluderIsTheOccluder) {
  // A hand in front of A with a dark patch (no depth) in its middle.
  const Picture measured = {
      "wwwwwwwwwwwwwwwwwwwwwwww",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwoooooohhhhhhhhooooooww",
      "wwoooooohhhhhhhhooooooww",
      "wwoooooohh____hhooooooww",
      "wwoooooohh____hhooooooww",
      "wwoooooohhhhhhhhooooooww",
      "wwoooooohhhhhhhhooooooww",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwwwwwwwwwwwwwwwwwwwwwww",
  };
  const Picture expected = {
      "........................",
      "..####################..",
      "..####################..",
      "..######........######..",
      "..######........######..",
      "..######........######..",
      "..######........######..",
      "..######........######..",
      "..######........######..",
      "..####################..",
      "..####################..",
      "........................",
  };
  const ObjectLabels combined = LabelA(kObjectA, measured, VisibilityRule::kCombined);
  ExpectMask(combined, expected);
  EXPECT_EQ(combined.stats.px_count_visib, 200 - 48);
  EXPECT_EQ(combined.stats.px_count_visib_assumed, 0);
  EXPECT_DOUBLE_EQ(combined.stats.mask_confidence, 1.0);
  // BOP19 counts the patch as visible.
  const ObjectLabels bop = LabelA(kObjectA, measured, VisibilityRule::kBop19);
  EXPECT_EQ(bop.stats.px_count_visib, 200 - 48 + 8);
  EXPECT_EQ(bop.stats.px_count_visib_assumed, 8);
}

TEST(VisibleMask, HoleOnTheObjectIsTheObject) {
  // A dark patch on A itself, and one across A's right edge into the wall behind it.
  const Picture measured = {
      "wwwwwwwwwwwwwwwwwwwwwwww",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwooo____oooooooooooooww",
      "wwooo____oooooooooooooww",
      "wwooo____oooooooooooooww",
      "wwoooooooooooooooooo____",
      "wwoooooooooooooooooo____",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwwwwwwwwwwwwwwwwwwwwwww",
  };
  const ObjectLabels combined = LabelA(kObjectA, measured, VisibilityRule::kCombined);
  ExpectMask(combined, AsMask(kObjectA));
  EXPECT_EQ(combined.stats.px_count_visib, 200);
  EXPECT_EQ(combined.stats.px_count_visib_assumed, 12 + 4);
  EXPECT_DOUBLE_EQ(combined.stats.mask_confidence, (200.0 - 16) / 200);
}

TEST(VisibleMask, ShadowBesideAnOccluderIsTheObjectAndTheOccludersEdgeIsNot) {
  // The hand's shadow (no depth) falls on A to its left; the hand's own edge column lost its depth too.
  const Picture measured = {
      "wwwwwwwwwwwwwwwwwwwwwwww",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwoooooo_____hhhhhooooww",
      "wwoooooo_____hhhhhooooww",
      "wwoooooo_____hhhhhooooww",
      "wwoooooo_____hhhhhooooww",
      "wwoooooo_____hhhhhooooww",
      "wwoooooo_____hhhhhooooww",
      "wwooooooooooooooooooooww",
      "wwooooooooooooooooooooww",
      "wwwwwwwwwwwwwwwwwwwwwwww",
  };
  const Picture expected = {
      "........................",
      "..####################..",
      "..####################..",
      "..##########......####..",
      "..##########......####..",
      "..##########......####..",
      "..##########......####..",
      "..##########......####..",
      "..##########......####..",
      "..####################..",
      "..####################..",
      "........................",
  };
  ExpectMask(LabelA(kObjectA, measured, VisibilityRule::kCombined), expected);
}

const Picture kObjectAtBorder = {
    "................",
    "AAAAAAAAAAAA....",
    "AAAAAAAAAAAA....",
    "AAAAAAAAAAAA....",
    "AAAAAAAAAAAA....",
    "AAAAAAAAAAAA....",
    "AAAAAAAAAAAA....",
    "AAAAAAAAAAAA....",
    "................",
};

TEST(VisibleMask, HoleAtTheImageBorder) {
  // On A: the hole is A. Inside a hand reaching in from the border: the hole is the hand.
  const Picture on_object = {
      "wwwwwwwwwwwwwwww",
      "oooooooooooowwww",
      "___ooooooooowwww",
      "___ooooooooowwww",
      "___ooooooooowwww",
      "oooooooooooowwww",
      "oooooooooooowwww",
      "oooooooooooowwww",
      "wwwwwwwwwwwwwwww",
  };
  ExpectMask(LabelA(kObjectAtBorder, on_object, VisibilityRule::kCombined), AsMask(kObjectAtBorder));
  const Picture in_hand = {
      "wwwwwwwwwwwwwwww",
      "hhhhhhoooooowwww",
      "___hhhoooooowwww",
      "___hhhoooooowwww",
      "___hhhoooooowwww",
      "hhhhhhoooooowwww",
      "oooooooooooowwww",
      "oooooooooooowwww",
      "wwwwwwwwwwwwwwww",
  };
  const Picture expected = {
      "................",
      "......######....",
      "......######....",
      "......######....",
      "......######....",
      "......######....",
      "############....",
      "############....",
      "................",
  };
  ExpectMask(LabelA(kObjectAtBorder, in_hand, VisibilityRule::kCombined), expected);
}

TEST(VisibleMask, NoDepthAtAllLeavesTheModelsMask) {
  // B, modelled, in front of A: without any depth both rules fall back, the combined one to the z-buffer
  // (A minus B), BOP19 to the amodal mask.
  const Picture model = {
      "........................",
      "..AAAAAAAAAAAAAAAAAAAA..",
      "..AAAAAAAAAAAAAAAAAAAA..",
      "..AAAAAAABBBBBBAAAAAAA..",
      "..AAAAAAABBBBBBAAAAAAA..",
      "..AAAAAAABBBBBBAAAAAAA..",
      "..AAAAAAAAAAAAAAAAAAAA..",
      "........................",
  };
  const Picture behind = ABehindB(model);
  const Picture nothing(8, std::string(24, '_'));
  const ObjectLabels combined = LabelA(model, nothing, VisibilityRule::kCombined, behind);
  ExpectMask(combined, AsMask(model));
  EXPECT_EQ(combined.masks.visible_measured, combined.masks.visible_model);
  EXPECT_EQ(combined.stats.px_count_valid, 0);
  EXPECT_EQ(combined.stats.px_count_visib_measured, 0);
  EXPECT_EQ(combined.stats.px_count_visib_assumed, 120 - 18);
  EXPECT_DOUBLE_EQ(combined.stats.mask_confidence, 0.0);
  EXPECT_EQ(LabelA(model, nothing, VisibilityRule::kBop19, behind).stats.px_count_visib, 120);
}

TEST(VisibleMask, ModelledOccluderWithoutDepthStaysAnOccluder) {
  // B is nearer than the sensor's minimum range: no depth on it. A is hidden behind it whatever the
  // depth says; B itself, wholly without depth but in front of A's measured surface, is visible.
  const Picture model = {
      "........................",
      "..AAAAAAAAAAAAAAAAAAAA..",
      "..AAAAAAABBBBBBAAAAAAA..",
      "..AAAAAAABBBBBBAAAAAAA..",
      "..AAAAAAABBBBBBAAAAAAA..",
      "..AAAAAAAAAAAAAAAAAAAA..",
      "........................",
  };
  const Picture behind = ABehindB(model);
  const Picture measured = {
      "wwwwwwwwwwwwwwwwwwwwwwww",
      "wwooooooooooooooooooooww",
      "wwooooooo______oooooooww",
      "wwooooooo______oooooooww",
      "wwooooooo______oooooooww",
      "wwooooooooooooooooooooww",
      "wwwwwwwwwwwwwwwwwwwwwwww",
  };
  const Picture expected = {
      "........................",
      "..####################..",
      "..#######......#######..",
      "..#######......#######..",
      "..#######......#######..",
      "..####################..",
      "........................",
  };
  ExpectMask(LabelA(model, measured, VisibilityRule::kCombined, behind), expected);
  EXPECT_EQ(LabelA(model, measured, VisibilityRule::kBop19, behind).stats.px_count_visib, 100)
      << "BOP19 gives A the pixels of B that have no depth";
  const RenderOutput render = RenderOf(model, behind);
  const DepthImage depth = MeasuredOf(measured);
  const ObjectLabels b = ComputeObjectLabels(render, CameraOf(model), &depth).at(1);
  EXPECT_EQ(b.stats.px_count_visib, 18);
  EXPECT_EQ(b.stats.px_count_visib_assumed, 18);
}

TEST(VisibleMask, OptionsAreChecked) {
  EXPECT_NO_THROW(VisibilityOptions{}.check());
  EXPECT_THROW((VisibilityOptions{.hole_search_px = 0}.check()), InputError);
  EXPECT_THROW((VisibilityOptions{.hole_edge_px = -1}.check()), InputError);
  EXPECT_THROW((VisibilityOptions{.hole_shadow_baseline_m = -0.1}.check()), InputError);
  EXPECT_EQ(ParseVisibilityRule("bop19", "test"), VisibilityRule::kBop19);
  EXPECT_EQ(ParseVisibilityRule(ToString(VisibilityRule::kCombined), "test"), VisibilityRule::kCombined);
  EXPECT_THROW(ParseVisibilityRule("bop", "test"), InputError);
}

}  // namespace
}  // namespace mocap
