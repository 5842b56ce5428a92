#include "cli/board_yaml.h"

#include "core/check.h"
#include "pipeline/yaml_read.h"

namespace mocap::cli {
namespace {

BoardSpec FromDoc(const pipeline::YamlDoc& doc) {
  const pipeline::YamlMap map(doc, doc.root, "board", {"type", "squares_x", "squares_y", "square_m", "marker_m", "dictionary"});
  BoardSpec spec;
  try {
    spec.type = BoardTypeFromString(map.Get<std::string>("type"));
  } catch (const InputError& e) {
    map.Fail("type", "must be charuco or checkerboard");
  }
  spec.squares_x = map.Get<int>("squares_x");
  spec.squares_y = map.Get<int>("squares_y");
  spec.square_m = map.Get<double>("square_m");
  if (spec.type == BoardType::kCharuco) {
    spec.marker_m = map.Get<double>("marker_m");
    spec.dictionary = map.Get<std::string>("dictionary");
  } else if (map.Has("marker_m") || map.Has("dictionary")) {
    map.Fail(map.Has("marker_m") ? "marker_m" : "dictionary", "belongs to a charuco board, not a checkerboard");
  }
  try {
    spec.check();
  } catch (const InputError& e) {
    throw InputError(map.Where(), e.what());
  }
  return spec;
}

}  // namespace

BoardSpec ReadBoardFile(const std::filesystem::path& path) { return FromDoc(pipeline::LoadYaml(path)); }

BoardSpec ParseBoard(const std::string& text, const std::string& file_name) {
  return FromDoc(pipeline::ParseYaml(text, file_name));
}

}  // namespace mocap::cli
