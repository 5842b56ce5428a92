#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/check.h"
#include "sim/depth_geometry.h"
#include "sim/kinect1_model.h"
#include "sim/kinect2_model.h"

namespace mocap::sim {
namespace {

DepthImage Wall(const PinholeCamera& camera, double z_m) { return DepthImage(camera.width, camera.height, static_cast<float>(z_m)); }

/// A fronto-parallel box face at `box_z` covering columns [u0, u1) and rows [v0, v1), before a wall.
DepthImage BoxBeforeWall(const PinholeCamera& camera, double box_z, double wall_z, int u0, int u1, int v0, int v1) {
  DepthImage depth = Wall(camera, wall_z);
  for (int v = v0; v < v1; ++v)
    for (int u = u0; u < u1; ++u) depth.at(u, v) = static_cast<float>(box_z);
  return depth;
}

TEST(Kinect1Model, WallNoiseMatchesKhoshelhamAt1And3Metres) {
  // The central 320x240 of the Kinect v1 image: 300k samples per depth are plenty.
  PinholeCamera camera = Kinect1ColorCamera();
  camera.width = 320;
  camera.height = 240;
  camera.cx -= 160;
  camera.cy -= 120;
  const Kinect1Options options;
  for (double z : {1.0, 3.0}) {
    // Wall depths spread over a few disparity steps so quantisation is sampled at all phases.
    double sum_sq = 0;
    size_t count = 0;
    for (int k = 0; k < 4; ++k) {
      const double wall = z + k * 0.25 * 0.0030711 * z * z;
      const Kinect1Frame frame = SimulateKinect1(Wall(camera, wall), {}, camera, options, 100 + k);
      for (float d : frame.depth_m.data) {
        if (!(d > 0)) continue;
        sum_sq += (d - wall) * (d - wall);
        ++count;
      }
    }
    const double measured = std::sqrt(sum_sq / count);
    const double expected = 1.425e-3 * z * z;
    EXPECT_NEAR(measured, expected, 0.10 * expected) << "z = " << z << " m: " << measured * 1e3 << " mm";
  }
}

TEST(Kinect1Model, DepthIsQuantisedInDisparitySteps) {
  const PinholeCamera camera = Kinect1ColorCamera();
  const Kinect1Options options;
  for (double z : {1.0, 2.0, 3.0}) {
    const Kinect1Frame frame = SimulateKinect1(Wall(camera, z), {}, camera, options, 5);
    std::set<float> levels;
    for (float d : frame.depth_m.data)
      if (d > 0 && std::abs(d - z) < 0.02 * z) levels.insert(d);
    ASSERT_GE(levels.size(), 3u);
    // Neighbouring levels near z differ by |a| z^2 (3.07 mm at 1 m).
    auto it = levels.lower_bound(static_cast<float>(z));
    const double step = *it - *std::prev(it);
    EXPECT_NEAR(step, 0.0030711 * z * z, 0.03 * 0.0030711 * z * z) << "z = " << z;
  }
  EXPECT_NEAR(Kinect1DepthFromDisparity(Kinect1DisparityFromDepth(1.234)), 1.234, 1e-12);
}

TEST(Kinect1Model, ProjectorShadowFallsOnTheSideAwayFromTheProjector) {
  // The projector sits at +x (right in the image): the box shadows the wall to its left.
  const PinholeCamera camera = Kinect1ColorCamera();
  Kinect1Options options;
  options.edge_invalid_probability = 0;
  options.ir_camera_x_m = 0;  // projector only
  const double box_z = 1.0, wall_z = 2.0;
  const DepthImage clean = BoxBeforeWall(camera, box_z, wall_z, 250, 390, 180, 300);
  const Kinect1Frame frame = SimulateKinect1(clean, {}, camera, options, 9);
  // Expected band width: fx * b * (1/box_z - 1/wall_z) = 525 * 0.05 * 0.5 = 13.1 px.
  int left = 0, right = 0;
  for (int u = 200; u < 250; ++u) left += frame.depth_m.at(u, 240) == 0;
  for (int u = 390; u < 440; ++u) right += frame.depth_m.at(u, 240) == 0;
  EXPECT_NEAR(left, 525 * 0.05 * (1 / box_z - 1 / wall_z), 1.5);
  EXPECT_EQ(right, 0);
  EXPECT_GE(frame.shadow_pixels, 12 * 120);
  // The IR camera (at -x) hides a band on the right side instead.
  const MaskImage hidden = ShadowMask(clean, camera, -0.025);
  int hidden_right = 0, hidden_left = 0;
  for (int u = 390; u < 440; ++u) hidden_right += hidden.at(u, 240);
  for (int u = 200; u < 250; ++u) hidden_left += hidden.at(u, 240);
  EXPECT_NEAR(hidden_right, 525 * 0.025 * 0.5, 1.5);
  EXPECT_EQ(hidden_left, 0);
}

TEST(Kinect1Model, EdgesDropPixelsOnlyAtDiscontinuities) {
  const PinholeCamera camera = Kinect1ColorCamera();
  Kinect1Options options;
  options.projector_x_m = options.ir_camera_x_m = 0;
  options.edge_invalid_probability = 1.0;
  const DepthImage clean = BoxBeforeWall(camera, 1.0, 1.5, 250, 390, 180, 300);
  const Kinect1Frame frame = SimulateKinect1(clean, {}, camera, options, 4);
  const MaskImage edges = DepthEdgeMask(clean, options.edge_jump_fraction, options.edge_min_jump_m);
  int edge_count = 0;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      if (edges.at(u, v)) ++edge_count;
      EXPECT_EQ(frame.depth_m.at(u, v) == 0, edges.at(u, v) == 1) << u << "," << v;
    }
  // Two one-pixel rings around the box face: 2 * (2*(140+120) + 4) - 8 corners counted once.
  EXPECT_NEAR(edge_count, 2 * 2 * (140 + 120), 16);
}

TEST(Kinect1Model, DarkSurfacesLoseTheirDepthInPatches) {
  // A box (instance 7) half of whose surface is dark, before a wall (instance 1) that is not.
  const PinholeCamera camera = Kinect1ColorCamera();
  Kinect1Options options;
  options.projector_x_m = options.ir_camera_x_m = 0;
  options.edge_invalid_probability = 0;
  const DepthImage clean = BoxBeforeWall(camera, 1.0, 1.5, 240, 402, 180, 300);
  LabelImage ids(camera.width, camera.height, 1);
  for (int v = 180; v < 300; ++v)
    for (int u = 240; u < 402; ++u) ids.at(u, v) = 7;
  DepthLoss loss;
  loss.fraction_by_instance = {{7, 0.5}};
  const Kinect1Frame frame = SimulateKinect1(clean, {}, camera, options, 21, loss, &ids);
  int lost_on_box = 0, lost_on_wall = 0, mixed_patches = 0;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) (ids.at(u, v) == 7 ? lost_on_box : lost_on_wall) += frame.depth_m.at(u, v) == 0;
  EXPECT_EQ(lost_on_wall, 0);
  EXPECT_EQ(frame.lost_pixels, lost_on_box);
  EXPECT_NEAR(lost_on_box / (162.0 * 120.0), 0.5, 0.1);
  // Whole 6x6 patches go together (the box's edges lie on patch boundaries: 240, 402; 180, 300).
  for (int v = 180; v < 300; v += 6)
    for (int u = 240; u < 402; u += 6) {
      int lost = 0;
      for (int dv = 0; dv < 6; ++dv)
        for (int du = 0; du < 6; ++du) lost += frame.depth_m.at(u + du, v + dv) == 0;
      mixed_patches += lost != 0 && lost != 36;
    }
  EXPECT_EQ(mixed_patches, 0);
  EXPECT_THROW((DepthLoss{{{7, 1.5}}, 6}.check()), InputError);
}

TEST(Kinect1Model, SameSeedSameFrameOtherSeedOtherNoise) {
  const PinholeCamera camera = Kinect1ColorCamera();
  const DepthImage clean = BoxBeforeWall(camera, 1.0, 2.0, 250, 390, 180, 300);
  const ColorImage color(camera.width, camera.height, Rgb8{100, 120, 140});
  const Kinect1Frame a = SimulateKinect1(clean, color, camera, {}, 11);
  const Kinect1Frame b = SimulateKinect1(clean, color, camera, {}, 11);
  const Kinect1Frame c = SimulateKinect1(clean, color, camera, {}, 12);
  EXPECT_EQ(a.depth_m.data, b.depth_m.data);
  EXPECT_EQ(a.raw_disparity.data, b.raw_disparity.data);
  EXPECT_EQ(a.color.data, b.color.data);
  EXPECT_NE(a.depth_m.data, c.depth_m.data);
  // Raw disparity and depth agree pixel for pixel.
  for (size_t i = 0; i < a.depth_m.data.size(); i += 97) {
    if (a.depth_m.data[i] > 0) {
      EXPECT_NEAR(Kinect1DepthFromDisparity(a.raw_disparity.data[i]), a.depth_m.data[i], 1e-6);
    } else {
      EXPECT_EQ(a.raw_disparity.data[i], kKinect1NoDisparity);
    }
  }
}

TEST(Kinect1Model, OptionsRejectImpossibleValues) {
  Kinect1Options options;
  options.max_depth_m = 20;
  EXPECT_THROW(options.check(), InputError);
  options = {};
  options.noise_coefficient_per_m = 1e-4;  // below the quantisation error
  EXPECT_THROW(options.check(), InputError);
  EXPECT_NO_THROW(Kinect1Options{}.check());
}

TEST(Kinect2Model, WallNoiseMatchesFankhauser) {
  const PinholeCamera camera = Kinect2DepthCamera();
  Kinect2Options options;
  for (double z : {1.0, 3.0}) {
    const Kinect2DepthFrame frame = SimulateKinect2Depth(Wall(camera, z), {}, camera, {}, options, 3);
    // Only near-normal pixels: the incidence on a fronto-parallel wall grows towards the corners.
    double sum_sq = 0;
    size_t count = 0;
    for (int v = 150; v < 274; ++v)
      for (int u = 190; u < 322; ++u) {
        sum_sq += std::pow(frame.depth_m.at(u, v) - z, 2);
        ++count;
      }
    const double expected = 1e-3 * (1.5 - 0.5 * z + 0.3 * z * z);
    EXPECT_NEAR(std::sqrt(sum_sq / count), expected, 0.10 * expected) << "z = " << z;
  }
  EXPECT_NEAR(Kinect2DepthSigmaM(1.0, 0.0), 1.3e-3, 1e-9);
  EXPECT_GT(Kinect2DepthSigmaM(1.0, RadFromDeg(75)), 2 * Kinect2DepthSigmaM(1.0, 0.0));
}

TEST(Kinect2Model, FlyingPixelsOnlyAtEdgesAndBetweenTheSurfaces) {
  const PinholeCamera camera = Kinect2DepthCamera();
  Kinect2Options options;
  options.tof_noise = false;
  options.flying_pixel_probability = 1.0;
  const DepthImage clean = BoxBeforeWall(camera, 1.0, 2.0, 200, 300, 150, 250);
  const Kinect2DepthFrame frame = SimulateKinect2Depth(clean, {}, camera, {}, options, 8);
  const MaskImage edges = DepthEdgeMask(clean, 0.0, options.edge_jump_m);
  int flying = 0;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const float z = frame.depth_m.at(u, v), z_clean = clean.at(u, v);
      if (std::abs(z - z_clean) < 1e-6) continue;
      ++flying;
      EXPECT_EQ(edges.at(u, v), 1) << u << "," << v;
      EXPECT_GT(z, 1.0);
      EXPECT_LT(z, 2.0);
    }
  EXPECT_EQ(flying, frame.flying_pixels);
  EXPECT_NEAR(flying, 2 * 2 * (100 + 100), 16);
}

TEST(Kinect2Model, ReflectiveSurfaceDeformsWithIncidence) {
  // A cylinder-like surface: depth varies across columns, so incidence grows towards its sides.
  const PinholeCamera camera = Kinect2DepthCamera();
  Kinect2Options options;
  options.tof_noise = false;
  options.flying_pixel_probability = 0;
  DepthImage clean(camera.width, camera.height, 0.0f);
  LabelImage ids(camera.width, camera.height, 0);
  const double radius = 0.06, centre_z = 1.0;
  for (int v = 100; v < 300; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const double x = (u - camera.cx) / camera.fx * centre_z;
      if (std::abs(x) >= 0.95 * radius) continue;
      clean.at(u, v) = static_cast<float>(centre_z - std::sqrt(radius * radius - x * x));
      ids.at(u, v) = 1;
    }
  const std::vector<ReflectiveSurface> reflective{{1, 0.8, 0.03}};
  const Kinect2DepthFrame frame = SimulateKinect2Depth(clean, ids, camera, reflective, options, 1);
  EXPECT_GT(frame.deformed_pixels, 1000);
  const int centre_u = static_cast<int>(camera.cx);
  EXPECT_LT(frame.depth_m.at(centre_u, 200) - clean.at(centre_u, 200), 0.5e-3);  // facing: ~no shift
  // Near the silhouette (incidence ~ 60-70 deg) the surface is pushed back by centimetres.
  const int side_u = centre_u + static_cast<int>(0.9 * radius / centre_z * camera.fx);
  const double shift = frame.depth_m.at(side_u, 200) - clean.at(side_u, 200);
  EXPECT_GT(shift, 0.008);
  EXPECT_LT(shift, 0.8 * 0.03);
  // Without the reflective entry nothing moves.
  const Kinect2DepthFrame matte = SimulateKinect2Depth(clean, ids, camera, {}, options, 1);
  EXPECT_EQ(matte.deformed_pixels, 0);
  EXPECT_FLOAT_EQ(matte.depth_m.at(side_u, 200), clean.at(side_u, 200));
}

TEST(Kinect2Model, ColourTimeLagsDepthTimeWithJitter) {
  Kinect2Options options;
  double sum = 0, sum_sq = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const double lag_ms = (Kinect2ColorTimeNs(1'000'000'000, i, options, 77) - 1'000'000'000) * 1e-6;
    sum += lag_ms;
    sum_sq += lag_ms * lag_ms;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, options.colour_delay_ms, 0.3);
  EXPECT_NEAR(std::sqrt(sum_sq / n - mean * mean), options.colour_jitter_ms, 0.3);
  EXPECT_EQ(Kinect2ColorTimeNs(0, 5, options, 1), Kinect2ColorTimeNs(0, 5, options, 1));
}

TEST(DepthGeometry, IncidenceOfATiltedPlane) {
  const PinholeCamera camera = Kinect2DepthCamera();
  // Plane z = 1 + 0.5 x (normal tilted by atan(0.5) = 26.6 deg about y), seen at the principal point.
  DepthImage depth(camera.width, camera.height, 0.0f);
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      const double xn = (u - camera.cx) / camera.fx;
      depth.at(u, v) = static_cast<float>(1.0 / (1.0 - 0.5 * xn));
    }
  const Image<float> angle = IncidenceAngleImage(depth, camera);
  EXPECT_NEAR(DegFromRad(angle.at(256, 212)), DegFromRad(std::atan(0.5)), 0.3);
}

}  // namespace
}  // namespace mocap::sim
