#pragma once
// The calibration board file (calib/boards/*.yaml, docs/calibration.md "Boards") onto BoardSpec: strict
// (unknown keys, wrong types and invalid values are errors naming file:line and the key).
#include <filesystem>
#include <string>

#include "calibrate/board.h"

namespace mocap::cli {

BoardSpec ReadBoardFile(const std::filesystem::path& path);
BoardSpec ParseBoard(const std::string& text, const std::string& file_name);

}  // namespace mocap::cli
