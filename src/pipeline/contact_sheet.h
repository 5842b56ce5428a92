#pragma once
// A contact sheet for a person to look at: a grid of frames of a session, each the recorded colour image
// with the label run's instance image over it (a translucent colour per instance and its outline), the
// frame index in the corner.
#include <filesystem>
#include <string>

namespace mocap {
class SessionReader;
}

namespace mocap::pipeline {

struct ContactSheetOptions {
  int columns = 4, rows = 3;  ///< frames are picked evenly over the session
  int cell_width_px = 320;    ///< each frame is scaled to this width (aspect kept)
  double alpha = 0.45;        ///< opacity of the label colours
  void check() const;         ///< throws InputError
};

/// Writes the PNG to `out_png`. Throws InputError when the session has no colour frames, a label image
/// is missing, or the file cannot be written.
void WriteContactSheet(const SessionReader& session, const std::string& camera, const std::filesystem::path& labels_dir,
                       const std::filesystem::path& out_png, const ContactSheetOptions& options = {});

}  // namespace mocap::pipeline
