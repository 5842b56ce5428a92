#include "pcd_reader.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/check.h"

namespace mocap::testing {
namespace {

struct Header {
  std::vector<std::string> fields;
  std::vector<int> sizes, counts;
  std::vector<char> types;
  int width = 0, height = 0, points = 0;
  std::string data;
};

/// LZF decompression (liblzf format, as PCL writes binary_compressed data).
std::vector<char> LzfDecompress(const std::vector<char>& in, size_t out_size, const std::string& path) {
  std::vector<char> out(out_size);
  size_t ip = 0, op = 0;
  const auto fail = [&] { throw InputError(Str(path, ": byte ", ip), "corrupt LZF data"); };
  while (ip < in.size()) {
    const unsigned ctrl = static_cast<unsigned char>(in[ip++]);
    if (ctrl < 32) {
      const size_t len = ctrl + 1;
      if (ip + len > in.size() || op + len > out_size) fail();
      std::memcpy(&out[op], &in[ip], len);
      ip += len;
      op += len;
      continue;
    }
    size_t len = ctrl >> 5;
    if (len == 7) {
      if (ip >= in.size()) fail();
      len += static_cast<unsigned char>(in[ip++]);
    }
    if (ip >= in.size()) fail();
    const size_t back = ((ctrl & 0x1f) << 8) + static_cast<unsigned char>(in[ip++]) + 1;
    len += 2;
    if (back > op || op + len > out_size) fail();
    for (size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];
  }
  if (op != out_size) fail();
  return out;
}

Header ReadHeader(std::istream& in, const std::string& path) {
  Header h;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string key;
    s >> key;
    if (key == "FIELDS") { for (std::string f; s >> f;) h.fields.push_back(f); }
    else if (key == "SIZE") { for (int v; s >> v;) h.sizes.push_back(v); }
    else if (key == "TYPE") { for (char c; s >> c;) h.types.push_back(c); }
    else if (key == "COUNT") { for (int v; s >> v;) h.counts.push_back(v); }
    else if (key == "WIDTH") s >> h.width;
    else if (key == "HEIGHT") s >> h.height;
    else if (key == "POINTS") s >> h.points;
    else if (key == "DATA") { s >> h.data; return h; }
  }
  throw InputError(Str(path, ":", line_no), "PCD header has no DATA line");
}

}  // namespace

PcdCloud ReadPcd(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open PCD file");
  Header h = ReadHeader(in, path);
  if (h.counts.empty()) h.counts.assign(h.fields.size(), 1);
  if (h.sizes.size() != h.fields.size() || h.types.size() != h.fields.size() || h.counts.size() != h.fields.size())
    throw InputError(path, "PCD header FIELDS/SIZE/TYPE/COUNT lengths differ");
  std::vector<size_t> offset(h.fields.size());
  size_t record = 0;
  int xyz[3] = {-1, -1, -1};
  for (size_t f = 0; f < h.fields.size(); ++f) {
    offset[f] = record;
    record += static_cast<size_t>(h.sizes[f]) * h.counts[f];
    for (int a = 0; a < 3; ++a)
      if (h.fields[f] == std::string(1, "xyz"[a])) {
        if (h.sizes[f] != 4 || h.types[f] != 'F') throw InputError(path, "x/y/z fields must be 4-byte floats");
        xyz[a] = static_cast<int>(f);
      }
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) throw InputError(path, "PCD file has no x, y, z fields");
  PcdCloud cloud{h.width, h.height, PointCloud(static_cast<size_t>(h.points))};
  const size_t n = cloud.points.size();
  if (h.data == "ascii") {
    std::vector<double> values;
    for (size_t i = 0; i < n; ++i) {
      std::string line;
      if (!std::getline(in, line)) throw InputError(Str(path, ": point ", i), "file ends early");
      std::istringstream s(line);
      for (size_t f = 0; f < h.fields.size(); ++f) {
        std::string token;
        s >> token;
        for (int a = 0; a < 3; ++a)
          if (xyz[a] == static_cast<int>(f)) cloud.points[i][a] = token == "nan" ? NAN : std::stod(token);
      }
    }
    return cloud;
  }
  std::vector<char> bytes;
  bool soa = false;
  if (h.data == "binary") {
    bytes.resize(n * record);
    if (!in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) throw InputError(path, "binary data ends early");
  } else if (h.data == "binary_compressed") {
    uint32_t sizes[2];
    if (!in.read(reinterpret_cast<char*>(sizes), 8)) throw InputError(path, "compressed header missing");
    std::vector<char> packed(sizes[0]);
    if (!in.read(packed.data(), sizes[0])) throw InputError(path, "compressed data ends early");
    if (sizes[1] != n * record) throw InputError(path, "uncompressed size does not match the header");
    bytes = LzfDecompress(packed, sizes[1], path);
    soa = true;  // binary_compressed stores each field for all points in turn
  } else {
    throw InputError(path, Str("unknown PCD DATA kind '", h.data, "'"));
  }
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      const size_t at = soa ? offset[xyz[a]] * n + i * 4 : i * record + offset[xyz[a]];
      float v;
      std::memcpy(&v, &bytes[at], 4);
      cloud.points[i][a] = v;
    }
  return cloud;
}

PointCloud FinitePoints(const PointCloud& points) {
  PointCloud out;
  out.reserve(points.size());
  for (const auto& p : points)
    if (p.allFinite()) out.push_back(p);
  return out;
}

}  // namespace mocap::testing
