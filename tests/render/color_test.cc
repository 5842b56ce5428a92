// Colour rendering: the coloured pixels are exactly those the label renderer's instance image gives the
// object, and the shading follows Lambert's law for the configured light.
#include <gtest/gtest.h>

#include <cmath>

#include "test_camera.h"
#include "render/color_renderer.h"
#include "render/primitives.h"

namespace mocap {
namespace {

using test::TestCamera;

Mesh Painted(Mesh mesh, const Eigen::Vector4f& rgba) {
  mesh.colors.assign(mesh.positions_m.size(), rgba);
  return mesh;
}

void CheckPixelsMatchInstances(bool distorted) {
  const PinholeCamera cam = TestCamera(distorted);
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  Renderer labels(*context);
  ColorRenderer colors(*context);
  const Mesh red = Painted(MakeBoxMesh({0.2, 0.15, 0.1}), {1, 0, 0, 1});
  const Mesh green = Painted(MakeSphereMesh(0.08, 800), {0, 1, 0, 1});
  const Rigid3d T_box = Rigid3d::FromRvec({0.4, 0.6, 0.1}, {-0.05, 0.02, 0.9});
  const Rigid3d T_ball = Rigid3d::FromRvec({0, 0, 0}, {0.12, 0.05, 0.8});  // in front of part of the box
  const std::vector<RenderItem> items = {{labels.Upload(red), T_box, 1}, {labels.Upload(green), T_ball, 2}};
  const std::vector<ColorRenderItem> color_items = {{colors.Upload(red), T_box}, {colors.Upload(green), T_ball}};
  const RenderOutput ids = labels.Render(cam, items);
  const RgbImage image = colors.Render(cam, color_items);
  ASSERT_EQ(image.width, cam.width);
  ASSERT_EQ(image.height, cam.height);
  int object_pixels = 0, mismatched = 0;
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const Rgb8Pixel p = image.at(u, v);
      const uint16_t id = ids.instance_ids.at(u, v);
      int expected = 0;  // which channel should carry the colour: 0 = background
      if (p[0] > 40 && p[1] == 0 && p[2] == 0) expected = 1;
      else if (p[1] > 40 && p[0] == 0 && p[2] == 0) expected = 2;
      object_pixels += id != 0;
      mismatched += expected != id;
      if (id == 0 && expected == 0) {
        EXPECT_NEAR(p[0], 0.18 * 255, 1) << u << "," << v;
        EXPECT_NEAR(p[2], 0.24 * 255, 1) << u << "," << v;
      }
    }
  }
  EXPECT_GT(object_pixels, 10000);
  // Same projection and pixel centres; only silhouette pixels whose centre lies on an edge may differ.
  EXPECT_LT(mismatched, object_pixels / 200) << "of " << object_pixels;
}

TEST(ColorRender, PixelsMatchInstanceImage) { CheckPixelsMatchInstances(false); }
TEST(ColorRender, PixelsMatchInstanceImageDistorted) { CheckPixelsMatchInstances(true); }

TEST(ColorRender, LambertShading) {
  const PinholeCamera cam = TestCamera(false);
  const auto context = RenderContext::Create({.platform = EglPlatform::kSurfaceless});
  const Mesh plane = Painted(MakeRectangleMesh(0.4, 0.4), {0.8f, 0.6f, 0.4f, 1});
  const Rigid3d T_camera_plane = Rigid3d::FromRvec({0, 0, 0}, {0, 0, 1.0});  // faces the camera
  for (double angle_deg : {0.0, 60.0}) {
    ColorRendererOptions options;
    options.ambient = 0.2, options.diffuse = 0.8;
    const double a = angle_deg * M_PI / 180;
    options.light_dir_camera = {std::sin(a), 0, -std::cos(a)};  // towards the light, camera frame
    ColorRenderer renderer(*context, options);
    const ColorRenderItem item{renderer.Upload(plane), T_camera_plane};
    const RgbImage image = renderer.Render(cam, std::span(&item, 1));
    const double shade = 0.2 + 0.8 * std::cos(a);
    const Rgb8Pixel p = image.at(320, 240);
    EXPECT_NEAR(p[0], 0.8 * shade * 255, 1.5) << angle_deg;
    EXPECT_NEAR(p[1], 0.6 * shade * 255, 1.5) << angle_deg;
    EXPECT_NEAR(p[2], 0.4 * shade * 255, 1.5) << angle_deg;
  }
}

}  // namespace
}  // namespace mocap
