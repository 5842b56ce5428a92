#include "render/conventions.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace mocap {
namespace {

TEST(Conventions, ClipMatrixReproducesOpenCvPixel) {
  const CanvasIntrinsics canvas{640, 480, 525.5, 524.0, 319.3, 241.7};
  const Eigen::Matrix4f P = GlClipFromCamera(canvas, 0.1, 10.0);
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.1, -0.2, 1.0), Eigen::Vector3d(-0.5, 0.3, 2.5), Eigen::Vector3d(0, 0, 0.3)}) {
    const Eigen::Vector4d clip = P.cast<double>() * p.homogeneous();
    EXPECT_NEAR(clip.w(), p.z(), 1e-6) << "clip w is the optical-axis depth";
    const Eigen::Vector2d pixel = PixelFromNdc(canvas, clip.head<2>() / clip.w());
    EXPECT_NEAR(pixel.x(), canvas.fx * p.x() / p.z() + canvas.cx, 1e-4);
    EXPECT_NEAR(pixel.y(), canvas.fy * p.y() / p.z() + canvas.cy, 1e-4);
  }
}

TEST(Conventions, NearAndFarMapToDepthRange) {
  const CanvasIntrinsics canvas{100, 80, 100, 100, 50, 40};
  const Eigen::Matrix4d P = GlClipFromCamera(canvas, 0.5, 4.0).cast<double>();
  const Eigen::Vector4d near_clip = P * Eigen::Vector4d(0, 0, 0.5, 1), far_clip = P * Eigen::Vector4d(0, 0, 4.0, 1);
  EXPECT_NEAR(near_clip.z() / near_clip.w(), -1.0, 1e-5);
  EXPECT_NEAR(far_clip.z() / far_clip.w(), 1.0, 1e-5);
}

TEST(Conventions, TopLeftPixelCentreIsOrigin) {
  // OpenCV pixel (0, 0) is the centre of the first GL window pixel: NDC (-1 + 1/W, -1 + 1/H).
  const CanvasIntrinsics canvas{640, 480, 500, 500, 320, 240};
  const Eigen::Vector2d pixel = PixelFromNdc(canvas, {-1.0 + 1.0 / 640, -1.0 + 1.0 / 480});
  EXPECT_NEAR(pixel.x(), 0.0, 1e-12);
  EXPECT_NEAR(pixel.y(), 0.0, 1e-12);
}

}  // namespace
}  // namespace mocap
