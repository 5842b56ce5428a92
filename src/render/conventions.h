#pragma once
// The one place where OpenCV's camera and pixel conventions meet OpenGL's (DESIGN.md "Conventions").
//
// OpenCV: camera x right, y down, z forward; pixel (u, v) = column u, row v, the centre of the top-left
// pixel at (0, 0); u = fx x/z + cx, v = fy y/z + cy.
// OpenGL: window coordinates have the centre of pixel (i, j) at (i + 0.5, j + 0.5), and glReadPixels
// returns row j = 0 first. We therefore map image row v to GL window row v (the picture is "upside down"
// for GL, which nobody looks at): then x_window = u + 0.5, y_window = v + 0.5, the rows read back are in
// image order with no flip, and the camera needs no axis flip either (clip w = +z, points in front of
// the camera have z > 0). Face winding is mirrored by this, so face culling stays off.
#include <Eigen/Core>

namespace mocap {

/// The pinhole part of a camera on a render canvas: intrinsics in OpenCV's pixel convention.
struct CanvasIntrinsics {
  int width = 0, height = 0;              ///< pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  ///< pixels, OpenCV convention
};

/// Clip-from-camera matrix such that a camera point (x, y, z), z in [near_m, far_m], rasterises at
/// OpenCV pixel (fx x/z + cx, fy y/z + cy) of `canvas`, with image row v in GL window row v.
/// x_ndc = (2 (fx x/z + cx) + 1) / W - 1, likewise y; z_ndc maps near to -1 and far to +1.
/// Precondition: 0 < near_m < far_m, canvas sizes and focal lengths positive.
Eigen::Matrix4f GlClipFromCamera(const CanvasIntrinsics& canvas, double near_m, double far_m);

/// Inverse of the x/y part of GlClipFromCamera (for tests): the OpenCV pixel of a point in
/// normalised device coordinates.
Eigen::Vector2d PixelFromNdc(const CanvasIntrinsics& canvas, const Eigen::Vector2d& ndc);

}  // namespace mocap
