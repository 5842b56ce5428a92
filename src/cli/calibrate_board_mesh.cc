// `mocaplabel calibrate board B --out DIR`: the board drawn for printing, and as a textured mesh (OBJ +
// MTL + PNG) whose frame is the board frame (calibrate/board.h), so that the simulator renders it and
// the object library can list it like any object.
#include "cli/calibrate_board_mesh.h"
#include "cli/calibrate_views.h"

#include <Eigen/LU>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "core/check.h"

namespace mocap::cli {
namespace {

namespace fs = std::filesystem;

void WriteImage(const fs::path& file, const cv::Mat& image) {
  if (!cv::imwrite(file.string(), image)) throw InputError(file.string(), "cannot be written");
}

}  // namespace

std::vector<fs::path> WriteBoardFiles(const BoardSpec& spec, const fs::path& out_dir, int pixels_per_square,
                                      double thickness_m, bool force) {
  spec.check();
  if (!(thickness_m > 0)) throw InputError("--thickness-mm", "must be > 0");
  const fs::path print = out_dir / "board.png", obj = out_dir / "board_mesh.obj", mtl = out_dir / "board_mesh.mtl",
                 texture = out_dir / "board_texture.png";
  for (const fs::path& f : {print, obj, mtl, texture}) RefuseExisting(f, force);
  fs::create_directories(out_dir);
  const BoardImage image = DrawBoard(spec, pixels_per_square, pixels_per_square / 2);
  WriteImage(print, image.gray);
  WriteImage(texture, image.gray);
  // The face is the whole drawn image (board and white margin): its corners in board metres, through the
  // inverse of H_pixel_board (a scale and an offset: the drawing is axis-aligned).
  const Eigen::Matrix3d H_board_pixel = image.H_pixel_board.inverse();
  auto board_xy = [&](double u, double v) {
    const Eigen::Vector3d p = H_board_pixel * Eigen::Vector3d(u, v, 1.0);
    return Eigen::Vector2d(p.x() / p.z(), p.y() / p.z());
  };
  const double W = image.gray.cols, H = image.gray.rows;
  // Pixel corners of the image (OpenCV convention: pixel centres at integers, edges at -0.5).
  const Eigen::Vector2d bl = board_xy(-0.5, H - 0.5), br = board_xy(W - 0.5, H - 0.5), tr = board_xy(W - 0.5, -0.5),
                        tl = board_xy(-0.5, -0.5);
  std::ofstream o(obj);
  o << "# " << ToString(spec.type) << " board " << spec.squares_x << "x" << spec.squares_y << ", " << spec.square_m
    << " m squares: mesh frame = board frame (docs/calibration.md), metres; front face z = 0\n"
    << "mtllib board_mesh.mtl\n";
  for (const Eigen::Vector2d& c : {bl, br, tr, tl}) o << "v " << c.x() << ' ' << c.y() << " 0\n";
  for (const Eigen::Vector2d& c : {bl, br, tr, tl}) o << "v " << c.x() << ' ' << c.y() << ' ' << -thickness_m << "\n";
  o << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";  // texture (0, 0) = bottom-left of the image
  // One material: the back and the edges take the texture too (one mesh, one texture for the loader);
  // only the printed face is ever seen by a camera that detects the board.
  o << "usemtl board\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";  // the printed face, towards +z
  o << "f 5/1 8/4 7/3\nf 5/1 7/3 6/2\nf 1/1 5/1 6/2\nf 1/1 6/2 2/2\nf 2/2 6/2 7/3\nf 2/2 7/3 3/3\n"
    << "f 3/3 7/3 8/4\nf 3/3 8/4 4/4\nf 4/4 8/4 5/1\nf 4/4 5/1 1/1\n";
  std::ofstream(mtl) << "newmtl board\nKd 1 1 1\nmap_Kd board_texture.png\n";
  if (!o || !std::ofstream(mtl, std::ios::app)) throw InputError(obj.string(), "cannot be written");
  return {print, obj, mtl, texture};
}

}  // namespace mocap::cli
