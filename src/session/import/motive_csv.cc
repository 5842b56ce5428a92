#include "session/import/motive_csv.h"

#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/text.h"
#include "session/import/text_parse.h"

namespace mocap::import {
namespace {

// The columns of one rigid body or marker: "<quantity> <axis>" ("Rotation W") -> column index.
struct ColumnGroup {
  std::string type, name, id;
  std::map<std::string, size_t> columns;
  int header_line = 0;
};

struct Header {
  std::vector<ColumnGroup> groups;
  size_t field_count = 0;
  size_t first_data_line = 0;  // 0-based index into lines
};

double LengthUnitM(const std::map<std::string, std::string>& info, const std::string& where) {
  auto it = info.find("Length Units");
  if (it == info.end()) return 1.0;  // exports before the field existed were in metres
  if (it->second == "Meters") return 1.0;
  if (it->second == "Centimeters") return 1e-2;
  if (it->second == "Millimeters") return 1e-3;
  throw InputError(where, Str("unknown Length Units ", QuoteForMessage(it->second), " (Meters, Centimeters or Millimeters)"));
}

std::map<std::string, std::string> ReadInfoLine(std::string_view line, const std::string& where) {
  const auto fields = SplitFields(line, ',');
  if (fields.empty() || Trim(fields[0]) != "Format Version")
    throw InputError(where, "not a Motive CSV export (line 1 must start with 'Format Version')");
  std::map<std::string, std::string> info;
  for (size_t i = 0; i + 1 < fields.size(); i += 2) info[std::string(Trim(fields[i]))] = std::string(Trim(fields[i + 1]));
  if (auto it = info.find("Rotation Type"); it != info.end() && it->second != "Quaternion")
    throw InputError(where, Str("Rotation Type is ", QuoteForMessage(it->second), "; export the take with quaternion rotations"));
  return info;
}

size_t FindRow(const std::vector<std::string_view>& lines, size_t column, std::string_view label, size_t end,
               const std::filesystem::path& file) {
  for (size_t i = 1; i < end; ++i) {
    const auto fields = SplitFields(lines[i], ',');
    if (fields.size() > column && Trim(fields[column]) == label) return i;
  }
  throw InputError(file.string(), Str("no header row labelled '", label, "' (not a Motive CSV export?)"));
}

Header ReadHeader(const std::vector<std::string_view>& lines, const std::filesystem::path& file) {
  size_t axis_row = 0;
  for (size_t i = 1; i < lines.size() && axis_row == 0; ++i)
    if (Trim(SplitFields(lines[i], ',')[0]) == "Frame") axis_row = i;
  if (axis_row < 2) throw InputError(file.string(), "no 'Frame,Time (Seconds),...' header row (truncated file?)");
  const auto type = SplitFields(lines[FindRow(lines, 1, "Type", axis_row, file)], ',');
  const auto name = SplitFields(lines[FindRow(lines, 1, "Name", axis_row, file)], ',');
  const size_t id_row = FindRow(lines, 1, "ID", axis_row, file);
  const auto id = SplitFields(lines[id_row], ',');
  const auto quantity = SplitFields(lines[axis_row - 1], ',');
  const auto axis = SplitFields(lines[axis_row], ',');
  const std::string where = Where(file, static_cast<int64_t>(axis_row + 1));
  if (axis.size() < 2 || Trim(axis[1]) != "Time (Seconds)")
    throw InputError(where, "second column must be 'Time (Seconds)'");
  for (const auto* row : {&type, &name, &quantity})
    if (row->size() != axis.size())
      throw InputError(where, Str("header rows have ", row->size(), " and ", axis.size(), " columns"));
  Header header;
  header.field_count = axis.size();
  header.first_data_line = axis_row + 1;
  for (size_t c = 2; c < axis.size(); ++c) {
    const std::string t(Trim(type[c])), n(Trim(name[c]));
    if (header.groups.empty() || header.groups.back().type != t || header.groups.back().name != n)
      header.groups.push_back({t, n, c < id.size() ? std::string(Trim(id[c])) : "", {}, static_cast<int>(axis_row + 1)});
    const std::string key = Str(Trim(quantity[c]), Trim(axis[c]).empty() ? "" : " ", Trim(axis[c]));
    if (!header.groups.back().columns.emplace(key, c).second)
      throw InputError(where, Str("column ", QuoteForMessage(key), " of ", QuoteForMessage(n), " appears twice"));
  }
  return header;
}

size_t Column(const ColumnGroup& group, const std::string& key, const std::filesystem::path& file) {
  auto it = group.columns.find(key);
  if (it == group.columns.end())
    throw InputError(Where(file, group.header_line), Str(group.type, " ", QuoteForMessage(group.name), " has no '", key, "' column"));
  return it->second;
}

// Reads the cells of `columns` in `row`: all present -> values; all blank -> empty; else InputError.
std::optional<std::vector<double>> ReadCells(const std::vector<std::string_view>& row, const std::vector<size_t>& columns,
                                             const std::string& what, const std::string& where) {
  size_t blank = 0;
  for (size_t c : columns) blank += Trim(row[c]).empty() ? 1 : 0;
  if (blank == columns.size()) return std::nullopt;
  if (blank != 0) throw InputError(where, Str(what, " is partly blank (", blank, " of ", columns.size(), " cells)"));
  std::vector<double> values;
  for (size_t c : columns) values.push_back(ParseDouble(row[c], Str(where, " column ", c + 1)));
  return values;
}

struct RigidBodyColumns {
  std::vector<size_t> pose;  // rotation x y z w, position x y z
  std::optional<size_t> error;
};

RigidBodyColumns RigidColumns(const ColumnGroup& g, const std::filesystem::path& file) {
  RigidBodyColumns cols;
  for (const char* key : {"Rotation X", "Rotation Y", "Rotation Z", "Rotation W", "Position X", "Position Y", "Position Z"})
    cols.pose.push_back(Column(g, key, file));
  if (auto it = g.columns.find("Mean Marker Error"); it != g.columns.end()) cols.error = it->second;
  return cols;
}

// A file cut short (a copy interrupted, `head`) still parses row by row; the header's own count of
// exported frames is what tells it from a short take.
void CheckExportedFrames(const MotiveTake& take, const std::filesystem::path& file) {
  auto it = take.info.find("Total Exported Frames");
  if (it == take.info.end()) return;  // older exports do not say
  const int64_t declared = ParseInt(it->second, Where(file, 1) + " Total Exported Frames");
  const auto present = static_cast<int64_t>(take.frame_ids.size());
  if (present < declared)
    throw InputError(file.string(), Str("the header declares ", declared, " exported frames ('Total Exported Frames') but ",
                                        present, " frame rows follow (truncated file?)"));
}

}  // namespace

MotiveTake ReadMotiveCsv(const std::filesystem::path& file, const MotiveOptions& options) {
  // Motive writes names in the Windows code page: a line that is not UTF-8 is read as Windows-1252.
  const std::string text = LinesToUtf8(ReadTextFile(file));
  auto lines = SplitLines(text);
  while (!lines.empty() && Trim(lines.back()).empty()) lines.pop_back();
  if (lines.empty()) throw InputError(file.string(), "empty file");
  MotiveTake take;
  take.file = file;
  take.info = ReadInfoLine(lines[0], Where(file, 1));
  take.length_unit_m = LengthUnitM(take.info, Where(file, 1));
  const Header header = ReadHeader(lines, file);

  std::vector<RigidBodyColumns> rigid_columns;
  std::vector<std::vector<size_t>> marker_columns;
  for (const auto& g : header.groups) {
    if (g.type == "Rigid Body") {
      rigid_columns.push_back(RigidColumns(g, file));
      take.rigid_bodies.push_back({g.name, g.id, {}, {}});
    } else if ((g.type == "Marker" || g.type == "Rigid Body Marker") && options.keep_markers) {
      marker_columns.push_back({Column(g, "Position X", file), Column(g, "Position Y", file), Column(g, "Position Z", file)});
      take.markers.push_back({g.name, g.type, {}});
    } else if (g.type != "Marker" && g.type != "Rigid Body Marker") {
      take.ignored_columns.push_back(Str(g.type, " ", g.name));
    }
  }

  for (size_t i = header.first_data_line; i < lines.size(); ++i) {
    const std::string where = Where(file, static_cast<int64_t>(i + 1));
    const auto row = SplitFields(lines[i], ',');
    if (row.size() != header.field_count)
      throw InputError(where, Str("row has ", row.size(), " fields, the header ", header.field_count, " (truncated file?)"));
    take.frame_ids.push_back(ParseInt(row[0], where));
    const int64_t stamp_ns = NanosecondsFromSeconds(row[1], where);
    if (!take.stamps_ns.empty() && stamp_ns < take.stamps_ns.back()) throw InputError(where, "time goes backwards");
    take.stamps_ns.push_back(stamp_ns);
    for (size_t b = 0; b < take.rigid_bodies.size(); ++b) {
      auto& body = take.rigid_bodies[b];
      PoseSample sample{.stamp_ns = stamp_ns, .status = PoseStatus::kMissing, .pose = {}};
      if (auto v = ReadCells(row, rigid_columns[b].pose, Str("rigid body ", QuoteForMessage(body.name)), where)) {
        const auto& x = *v;
        sample.status = PoseStatus::kValid;
        sample.pose = Rigid3d(QuaternionNearlyUnit(x[3], x[0], x[1], x[2], where),
                              Eigen::Vector3d(x[4], x[5], x[6]) * take.length_unit_m);
      }
      body.samples.push_back(sample);
      double error_m = std::numeric_limits<double>::quiet_NaN();
      if (rigid_columns[b].error && !Trim(row[*rigid_columns[b].error]).empty())
        error_m = ParseDouble(row[*rigid_columns[b].error], where) * take.length_unit_m;
      body.mean_marker_error_m.push_back(error_m);
    }
    for (size_t m = 0; m < take.markers.size(); ++m) {
      auto v = ReadCells(row, marker_columns[m], Str("marker ", QuoteForMessage(take.markers[m].name)), where);
      std::optional<Eigen::Vector3d> position;
      if (v) position = Eigen::Vector3d((*v)[0], (*v)[1], (*v)[2]) * take.length_unit_m;
      take.markers[m].positions_m.push_back(position);
    }
  }
  CheckExportedFrames(take, file);
  return take;
}

}  // namespace mocap::import
