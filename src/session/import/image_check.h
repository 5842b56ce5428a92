#pragma once
// Importers link source images into sessions without decoding them; this cheap check reads only the
// first and last bytes so that an image cut short (a partial download, a full disk) is reported at
// import, naming the file, instead of surfacing later as a broken frame.
#include <filesystem>

namespace mocap::import {

/// Throws InputError naming `image` when it is a PNG without its closing IEND chunk, a JPEG without
/// its EOI marker, or neither (by its first bytes). Precondition: the file exists.
void CheckImageComplete(const std::filesystem::path& image);

/// What a session accepts for an imported image: colour .png/.jpg/.jpeg, depth .png (by name, checked
/// even when the file is absent), and, when the file exists, CheckImageComplete. Throws InputError.
void CheckImportableImage(const std::filesystem::path& image, bool depth);

}  // namespace mocap::import
