#pragma once
// The files of `mocaplabel calibrate board`: board.png to print, and board_mesh.obj/.mtl with
// board_texture.png, a box of `thickness_m` whose front face (z = 0, towards +z) carries the drawing, in
// the board frame of calibrate/board.h (metres).
#include <filesystem>
#include <vector>

#include "calibrate/board.h"

namespace mocap::cli {

/// Writes the four files into `out_dir`; InputError when one exists (unless `force`) or cannot be written.
std::vector<std::filesystem::path> WriteBoardFiles(const BoardSpec& spec, const std::filesystem::path& out_dir,
                                                   int pixels_per_square, double thickness_m, bool force);

}  // namespace mocap::cli
