// The optional colour test on depth holes (label/hole_colour.h): hand-built frames, one character per
// pixel for the measured depth, the colour image and the expected mask.
#include <gtest/gtest.h>

#include <cmath>
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

constexpr float kObject_m = 1.0f;

/// Object 1 rendered over the whole image at 1 m.
RenderOutput ObjectEverywhere(int w, int h) {
  RenderOutput r{LabelImage(w, h, 1), DepthImage(w, h, kObject_m), {}};
  ObjectLayer layer{1, {0, 0, w, h}, std::vector<float>(static_cast<size_t>(w) * h, kObject_m)};
  layer.px_count_all = w * h;
  r.layers.push_back(std::move(layer));
  return r;
}

/// 'o' the object's surface measured, '_' no depth.
DepthImage DepthOf(const Picture& p) {
  DepthImage d(static_cast<int>(p[0].size()), static_cast<int>(p.size()), 0.0f);
  for (int v = 0; v < d.height; ++v)
    for (int u = 0; u < d.width; ++u) d.at(u, v) = p[v][u] == 'o' ? kObject_m : 0.0f;
  return d;
}

/// 'y' the bottle's yellow, 'd' the same yellow in shade, 's' skin, 'k' too dark to tell; BGR bytes.
std::vector<uint8_t> BgrOf(const Picture& p) {
  std::vector<uint8_t> bgr;
  for (const std::string& row : p)
    for (char c : row) {
      const int r = c == 'y' ? 228 : c == 'd' ? 114 : c == 's' ? 222 : 20;
      const int g = c == 'y' ? 186 : c == 'd' ? 93 : c == 's' ? 178 : 20;
      const int b = c == 'y' ? 38 : c == 'd' ? 19 : c == 's' ? 148 : 22;
      bgr.insert(bgr.end(), {static_cast<uint8_t>(b), static_cast<uint8_t>(g), static_cast<uint8_t>(r)});
    }
  return bgr;
}

/// A mesh of one triangle per colour, of the given areas (m^2), for MeshColours.
Mesh TriangleMesh(const std::vector<std::pair<Eigen::Vector4f, float>>& colour_areas) {
  Mesh mesh;
  for (const auto& [colour, area] : colour_areas) {
    const auto base = static_cast<uint32_t>(mesh.positions_m.size());
    const float side = std::sqrt(2.0f * area);
    mesh.positions_m.insert(mesh.positions_m.end(), {{0, 0, 0}, {side, 0, 0}, {0, side, 0}});
    mesh.colors.insert(mesh.colors.end(), {colour, colour, colour});
    mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2});
  }
  return mesh;
}

const Eigen::Vector4f kYellow{228 / 255.0f, 186 / 255.0f, 38 / 255.0f, 1}, kBlue{30 / 255.0f, 60 / 255.0f, 140 / 255.0f, 1};

/// The object's visible mask drawn as '#' / '.', with the colour test on or off.
Picture Label(const Picture& depth, const Picture& colour, bool hole_colour, const ColourHistogram* mesh = nullptr,
              int min_reference_px = 200) {
  const PinholeCamera camera = CameraOf(depth);
  const RenderOutput render = ObjectEverywhere(camera.width, camera.height);
  const DepthImage measured = DepthOf(depth);
  const std::vector<uint8_t> bgr = BgrOf(colour);
  VisibilityOptions options;
  options.hole_colour = hole_colour;
  options.hole_colour_min_reference_px = min_reference_px;
  HoleColours colours{{camera.width, camera.height, bgr.data(), 3 * static_cast<size_t>(camera.width)}, {}};
  if (mesh) colours.mesh_colours[1] = mesh;
  const ObjectLabels labels = ComputeObjectLabels(render, camera, &measured, options, &colours).at(0);
  Picture p = depth;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) p[v][u] = labels.masks.at(labels.masks.visible_measured, u, v) ? '#' : '.';
  return p;
}

// A hole in the middle of the object: its left part shows the object's yellow (a dark patch: no
// depth, same colour), its right part skin (a hand nearer than the sensor's range), its last pixel in
// the second row too dark to tell.
const Picture kDepth = {
    "oooooooooooo",
    "oo_________o",
    "oo________oo",
    "oooooooooooo",
};
const Picture kColour = {
    "yyyyyyyyyyyy",
    "yyyydssssskk",
    "yyyyyssssskk",
    "yyyyyyyyyyyy",
};

TEST(HoleColour, OnByDefaultButWithoutAColourImageTheHoleRuleDecides) {
  EXPECT_TRUE(VisibilityOptions{}.hole_colour);
  const PinholeCamera camera = CameraOf(kDepth);
  const DepthImage measured = DepthOf(kDepth);
  const ObjectLabels labels = ComputeObjectLabels(ObjectEverywhere(camera.width, camera.height), camera, &measured).at(0);
  EXPECT_EQ(labels.stats.px_count_visib, camera.width * camera.height);
}

TEST(HoleColour, OffTheHoleRuleDecides) {
  EXPECT_EQ(Lines(Label(kDepth, kColour, false, nullptr, 1)),
            Lines({"############", "############", "############", "############"}));
}

TEST(HoleColour, AHoleOfAForeignColourIsHiddenOneOfTheObjectsIsNot) {
  // Reference: the 28 bright pixels with depth (all yellow). The shaded yellow keeps its chromaticity.
  EXPECT_EQ(Lines(Label(kDepth, kColour, true, nullptr, 20)),
            Lines({"############", "#####.....##", "#####.....##", "############"}));
}

TEST(HoleColour, TooFewPixelsWithDepthAndNoMeshColoursLeaveTheMask) {
  EXPECT_EQ(Lines(Label(kDepth, kColour, true, nullptr, 200)),
            Lines({"############", "############", "############", "############"}));
}

TEST(HoleColour, TheMeshsColoursJudgeAnObjectWithoutDepth) {
  // No depth at all (the object nearer than the sensor's range): its mesh says yellow and blue.
  const Picture no_depth(4, std::string(12, '_'));
  const ColourHistogram mesh = MeshColours(TriangleMesh({{kYellow, 0.01f}, {kBlue, 0.002f}}), VisibilityOptions{});
  EXPECT_EQ(Lines(Label(no_depth, kColour, true, &mesh)),
            Lines({"############", "#####.....##", "#####.....##", "############"}));
}

TEST(HoleColour, AColourEitherReferenceShowsIsTheObjects) {
  // The pixels with depth show only yellow, but the mesh has skin-coloured parts: nothing is foreign.
  const Eigen::Vector4f skin{222 / 255.0f, 178 / 255.0f, 148 / 255.0f, 1};
  const ColourHistogram mesh = MeshColours(TriangleMesh({{kYellow, 0.01f}, {skin, 0.01f}}), VisibilityOptions{});
  EXPECT_EQ(Lines(Label(kDepth, kColour, true, &mesh, 20)),
            Lines({"############", "############", "############", "############"}));
}

TEST(HoleColour, MeshColoursAreWeightedByArea) {
  const VisibilityOptions options;
  const ColourHistogram mesh = MeshColours(TriangleMesh({{kYellow, 0.03f}, {kBlue, 0.01f}}), options);
  EXPECT_NEAR(mesh.total(), 0.04, 1e-6);
  EXPECT_NEAR(mesh.ShareAround(mesh.Bin(228, 186, 38)), 0.75, 1e-6);
  EXPECT_NEAR(mesh.ShareAround(mesh.Bin(30, 60, 140)), 0.25, 1e-6);
  EXPECT_EQ(mesh.Bin(20, 20, 22), -1);  // too dark
  EXPECT_EQ(MeshColours(Mesh{}, options).total(), 0.0);
}

TEST(HoleColour, AColourImageOfTheWrongSizeIsRefused) {
  const PinholeCamera camera = CameraOf(kDepth);
  const RenderOutput render = ObjectEverywhere(camera.width, camera.height);
  const DepthImage measured = DepthOf(kDepth);
  const std::vector<uint8_t> bgr(3 * 5 * 5, 0);
  const HoleColours colours{{5, 5, bgr.data(), 15}, {}};
  EXPECT_THROW(ComputeObjectLabels(render, camera, &measured, VisibilityOptions{.hole_colour = true}, &colours),
               InputError);
}

TEST(HoleColour, OptionsAreChecked) {
  EXPECT_THROW((VisibilityOptions{.hole_colour_bins = 1}.check()), InputError);
  EXPECT_THROW((VisibilityOptions{.hole_colour_max_share = 1.0}.check()), InputError);
  EXPECT_THROW((VisibilityOptions{.hole_colour_min_reference_px = 0}.check()), InputError);
}

}  // namespace
}  // namespace mocap
