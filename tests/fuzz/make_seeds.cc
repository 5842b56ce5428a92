// Writes the seed corpus of one fuzzer (tests/fuzz/fuzz_<name>.cc) from the real files in
// ../shared/realdata and the project's own calib/, meshes/, scenarios/ and docs/, cut to sizes the
// fuzzers run fast on, in the input layout each harness reads (selector byte, files joined by '\0').
// Usage: mocap_fuzz_seeds NAME OUT_DIR
#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "session/import/tracker_import.h"
#include "session/manifest.h"
#include "session/png_gray16.h"
#include "session/png_write.h"
#include "session/writer.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kReal = fs::path(MOCAP_SHARED_DIR) / "realdata";
const fs::path kSource = MOCAP_SOURCE_DIR;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// Writes OUT/<name>: the optional selector byte, then the parts joined with '\0'.
void Seed(const fs::path& out, const std::string& name, int selector, const std::vector<std::string>& parts) {
  std::ofstream file(out / name, std::ios::binary);
  if (selector >= 0) file.put(static_cast<char>(selector));
  for (size_t i = 0; i < parts.size(); ++i) file << (i ? std::string(1, '\0') : "") << parts[i];
}

std::string FirstLines(const std::string& text, size_t lines) {
  size_t end = 0;
  for (size_t i = 0; i < lines; ++i) {
    end = text.find('\n', end);
    if (end == std::string::npos) return text;
    ++end;
  }
  return text.substr(0, end);
}

/// The first `count` members of a JSON object (in the object's key order).
json FirstMembers(const json& object, size_t count) {
  json out = json::object();
  for (auto it = object.begin(); it != object.end() && out.size() < count; ++it) out[it.key()] = it.value();
  return out;
}

void SeedsBop(const fs::path& out) {
  const fs::path scene = kReal / "bop_lmo_scene2/test/000002";
  const json gt = json::parse(ReadFile(scene / "scene_gt.json"));
  const json cameras = json::parse(ReadFile(scene / "scene_camera.json"));
  const std::string models = ReadFile(kReal / "bop_lmo_scene2/models/models_info.json");
  for (size_t frames : {1, 3}) {
    json gt_cut = FirstMembers(gt, frames), cameras_cut = json::object();
    for (const auto& [key, value] : gt_cut.items()) cameras_cut[key] = cameras.at(key);
    Seed(out, "lmo_" + std::to_string(frames), -1, {gt_cut.dump(1), cameras_cut.dump(1), models});
  }
}

void SeedsTum(const fs::path& out) {
  const fs::path desk = kReal / "tum_fr1_desk_9frames", xyz = kReal / "tum_fr1_xyz_index";
  Seed(out, "fr1_desk", -1,
       {FirstLines(ReadFile(desk / "rgb.txt"), 30), FirstLines(ReadFile(desk / "depth.txt"), 30),
        FirstLines(ReadFile(desk / "groundtruth.txt"), 120)});
  Seed(out, "fr1_xyz", -1,  // its index files lost the '#' of a header line
       {FirstLines(ReadFile(xyz / "rgb.txt"), 30), FirstLines(ReadFile(xyz / "depth.txt"), 30),
        FirstLines(ReadFile(kReal / "tum_groundtruth_evo/freiburg1_xyz-groundtruth.txt"), 120)});
  Seed(out, "drift_short", -1, {"", "", ReadFile(kReal / "tum_groundtruth_evo/freiburg1_xyz-rgbdslam_drift_short.txt")});
}

void SeedsMotive(const fs::path& out) {
  Seed(out, "neon_take", -1, {FirstLines(ReadFile(kReal / "optitrack_neon_calib/optitrack_take.csv"), 12)});
}

/// A PLUS sequence cut to its first `frames` frames (DimSize rewritten to match).
std::string CutPlus(const std::string& text, int frames) {
  std::istringstream in(text);
  std::string line, out;
  const std::string last = "Seq_Frame" + std::string(4 - std::to_string(frames).size(), '0') + std::to_string(frames) + "_";
  while (std::getline(in, line)) {
    if (line.rfind(last, 0) == 0) break;
    if (line.rfind("DimSize", 0) == 0)  // "DimSize = 0 0 93": the last number is the frame count
      line = line.substr(0, line.rfind(' ', line.find_last_not_of(' '))) + " " + std::to_string(frames);
    out += line + "\n";
  }
  return out + "ElementDataFile = LOCAL\n";
}

void SeedsPlus(const fs::path& out) {
  for (const char* name : {"ReferenceToRASCalibration.igs.mha", "TransformInterpolationTest.igs.mha",
                           "WaterTankBottomTranslationTrackerBuffer-trimmed.igs.mha"})
    Seed(out, name, -1, {CutPlus(ReadFile(kReal / "plus_ndi_tracking" / name), 6)});
}

/// A session folder as the session fuzzer's input: manifest, then the streams, first `lines` lines each.
void SeedSession(const fs::path& out, const std::string& name, const fs::path& session, size_t lines) {
  json manifest = json::parse(ReadFile(session / "manifest.json"));
  if (lines < SIZE_MAX) manifest["complete"] = false;  // cut streams: not as closed
  std::vector<std::string> parts = {manifest.dump(1)};
  std::vector<fs::path> streams = mocap::SessionStreamFiles(mocap::LoadManifest(session));
  streams.front() = "events.jsonl";
  std::rotate(streams.begin(), streams.begin() + 1, streams.end());
  for (const fs::path& stream : streams)
    parts.push_back(fs::exists(session / stream) ? FirstLines(ReadFile(session / stream), lines) : "");
  Seed(out, name, 0, parts);
  Seed(out, name + "_reframed_skip", 3, parts);
}

void SeedsSession(const fs::path& out) {
  const fs::path scratch = out.parent_path() / "seed_sessions";
  fs::remove_all(scratch);
  mocap::SessionManifest manifest;
  manifest.software_version = manifest.source = "fuzz seed";
  mocap::CameraStreamInfo camera;
  camera.name = camera.model = "kinect1";
  camera.color_camera.width = 640, camera.color_camera.height = 480;
  camera.color_camera.fx = 517.3, camera.color_camera.fy = 516.5, camera.color_camera.cx = 318.6, camera.color_camera.cy = 255.3;
  camera.color_camera.dist = {0.2624, -0.9531, -0.0054, 0.0026, 1.1633, 0, 0, 0};
  camera.depth_camera = camera.color_camera;
  camera.camera_body = "cam";
  manifest.cameras = {camera};
  manifest.trackers = {{"ndi", "ndi", "P9-01", "tracker", {"cam", "obj"}}};
  {
    auto writer = mocap::SessionWriter::Create(scratch / "synthetic", manifest);
    for (int i = 0; i < 4; ++i) {
      writer->AddCameraFrameFiles("kinect1", {i, 600'000 * i, 1'000'000'000 + 33'333'333LL * i, "", "", ""},
                                  scratch / "absent.png", scratch / "absent_depth.png");
      for (const char* body : {"cam", "obj"}) {
        mocap::TrackerRecord record;
        record.body = body, record.device_frame = i, record.stamp_ns = 990'000'000 + 20'000'000LL * i;
        record.status = i == 2 ? mocap::PoseStatus::kMissing : mocap::PoseStatus::kValid;
        record.T_frame_body = mocap::Rigid3d::FromRvec({0.1 * i, -0.2, 0.3}, {0.01, 0.02 * i, 1.5});
        writer->WriteTrackerSample("ndi", record);
      }
    }
    writer->WriteEvent({42, "reconnect", "ndi", "port 2 came back"});
    writer->Close();
  }
  SeedSession(out, "synthetic", scratch / "synthetic", SIZE_MAX);
  mocap::import::ImportPlus(kReal / "plus_ndi_tracking/ReferenceToRASCalibration.igs.mha", scratch / "plus");
  SeedSession(out, "plus_reference", scratch / "plus", 12);
  fs::remove_all(scratch);
}

void SeedsPng(const fs::path& out) {
  const fs::path real = kReal / "tum_fr1_desk_9frames/depth/1305031453.374112.png";
  const std::string bytes = ReadFile(real);
  Seed(out, "tum_depth", 0, {bytes});
  Seed(out, "tum_depth_reframed", 1, {bytes});
  const auto depth = mocap::DecodeGray16Png({reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()}, 1.0, real.string());
  cv::Mat units(depth->height, depth->width, CV_16UC1);
  for (int v = 0; v < depth->height; ++v)
    for (int u = 0; u < depth->width; ++u) units.at<uint16_t>(v, u) = static_cast<uint16_t>(depth->at(u, v));
  const cv::Mat crop = units(cv::Rect(300, 200, 40, 30)).clone();
  const std::vector<uint8_t> ours = mocap::EncodeGray16Png(crop);
  Seed(out, "tum_crop_ours", 0, {std::string(ours.begin(), ours.end())});
  std::vector<uint8_t> libpng;  // libpng picks a filter per row
  cv::imencode(".png", crop, libpng, {cv::IMWRITE_PNG_COMPRESSION, 9});
  Seed(out, "tum_crop_libpng", 0, {std::string(libpng.begin(), libpng.end())});
  for (uint8_t filter = 0; filter < 5; ++filter) {  // synthesised 5x4 images, one filter type each
    std::string rows = {4, 3, 0};
    for (int v = 0; v < 4; ++v) {
      rows += static_cast<char>(filter);
      for (int b = 0; b < 10; ++b) rows += static_cast<char>(crop.data[v * 80 + b]);
    }
    Seed(out, "synthetic_filter" + std::to_string(filter), 2, {rows});
  }
}

/// The ```yaml blocks of a markdown page.
std::vector<std::string> YamlBlocks(const fs::path& page) {
  std::istringstream in(ReadFile(page));
  std::vector<std::string> blocks;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside && line.rfind("```yaml", 0) == 0) inside = true, blocks.emplace_back();
    else if (inside && line.rfind("```", 0) == 0) inside = false;
    else if (inside) blocks.back() += line + "\n";
  }
  return blocks;
}

void SeedsYaml(const fs::path& out) {
  for (const auto& entry : fs::directory_iterator(kSource / "calib"))
    if (entry.path().extension() == ".yaml") Seed(out, "rig_" + entry.path().stem().string(), 0, {ReadFile(entry.path())});
  Seed(out, "objects", 1, {ReadFile(kSource / "meshes/objects.yaml")});
  for (const auto& entry : fs::directory_iterator(kSource / "scenarios"))
    if (entry.path().extension() == ".yaml") Seed(out, "scenario_" + entry.path().stem().string(), 2, {ReadFile(entry.path())});
  const std::pair<const char*, int> pages[] = {{"capture.md", 0}, {"rig.md", 0}, {"objects.md", 1}, {"simulation.md", 2}};
  for (const auto& [page, selector] : pages) {
    const std::vector<std::string> blocks = YamlBlocks(kSource / "docs" / page);
    for (size_t i = 0; i < blocks.size(); ++i)
      Seed(out, std::string("docs_") + page + "_" + std::to_string(i), selector, {blocks[i]});
  }
  Seed(out, "pointer", 3, {"# pointer tip by pivot calibration\npointer_body: pointer_body\ntip_m: [0.012, 0.021, -0.175]\n"});
  Seed(out, "landmarks", 4, {"unit: mm\nlandmarks:\n  - {name: plug_1, mesh: [-135, 0, 305]}\n  - {name: plug_4, mesh: [135, 0, 305]}\n"
                             "  - {name: pulley, mesh: [227, 0, 105]}\n  - name: filter\n    mesh: [60, -228, 110]\n"});
}

/// The first `vertices` vertices of a text PLY with the faces among them, as PLY, OBJ and STL text.
void SeedsMeshFrom(const fs::path& out, const fs::path& ply, size_t vertices) {
  std::istringstream in(ReadFile(ply));
  std::string line;
  size_t vertex_count = 0, face_count = 0;
  std::vector<std::string> vertex_rows, properties;
  std::vector<std::array<size_t, 3>> faces;
  std::string element;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string keyword;
    size_t count = 0;
    words >> keyword;
    if (keyword == "element" && words >> element >> count) (element == "vertex" ? vertex_count : face_count) = count;
    if (keyword == "property" && element == "vertex") properties.push_back(line);
  }
  std::vector<std::array<double, 3>> xyz;
  for (size_t i = 0; i < vertex_count && std::getline(in, line); ++i)
    if (i < vertices) {
      vertex_rows.push_back(line);
      std::istringstream words(line);
      xyz.push_back({});
      words >> xyz.back()[0] >> xyz.back()[1] >> xyz.back()[2];
    }
  for (size_t i = 0; i < face_count && std::getline(in, line); ++i) {
    std::istringstream words(line);
    size_t n, a, b, c;
    if (words >> n >> a >> b >> c && n == 3 && a < vertices && b < vertices && c < vertices) faces.push_back({a, b, c});
  }
  const std::string stem = ply.stem().string();
  std::string text = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertex_rows.size()) + "\n";
  for (const std::string& p : properties)
    if (p.find(" list ") == std::string::npos) text += p + "\n";
  text += "element face " + std::to_string(faces.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const std::string& row : vertex_rows) text += row + "\n";
  std::string obj, stl = "solid " + stem + "\n";
  for (const auto& p : xyz) obj += "v " + std::to_string(p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
  for (const auto& f : faces) {
    text += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    obj += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " -" + std::to_string(xyz.size() - f[2]) + "\n";
    stl += "facet normal 0 0 1\nouter loop\n";
    for (size_t k : f)
      stl += "vertex " + std::to_string(xyz[k][0]) + " " + std::to_string(xyz[k][1]) + " " + std::to_string(xyz[k][2]) + "\n";
    stl += "endloop\nendfacet\n";
  }
  Seed(out, stem + "_cut.ply", 0, {text});
  Seed(out, stem + "_cut.obj", 1, {obj});
  Seed(out, stem + "_cut.stl", 2, {stl + "endsolid " + stem + "\n"});
}

void SeedsMesh(const fs::path& out) {
  SeedsMeshFrom(out, kReal / "bop_lmo_scene2/models/obj_000001.ply", 150);
  SeedsMeshFrom(out, kReal / "stanford_bunny/reconstruction/bun_zipper_res3.ply", 150);
  for (const char* name : {"hand.ply", "funnel.ply"}) Seed(out, name, 0, {ReadFile(kSource / "meshes" / name)});
  std::string stl(80, ' ');  // a binary STL of two triangles
  const uint32_t count = 2;
  stl.append(reinterpret_cast<const char*>(&count), 4);
  for (int t = 0; t < 2; ++t) {
    const float values[12] = {0, 0, 1, 0, 0, 0, 0.1f, 0, 0, 0, 0.1f * t, 0.1f};
    stl.append(reinterpret_cast<const char*>(values), sizeof(values));
    stl.append(2, '\0');
  }
  Seed(out, "two_triangles.stl", 2, {stl});
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: mocap_fuzz_seeds NAME OUT_DIR\n";
    return 2;
  }
  const std::string name = argv[1];
  const fs::path out = argv[2];
  fs::create_directories(out);
  const std::pair<const char*, void (*)(const fs::path&)> writers[] = {
      {"bop", SeedsBop},   {"tum", SeedsTum}, {"motive", SeedsMotive}, {"plus", SeedsPlus},
      {"session", SeedsSession}, {"png", SeedsPng}, {"yaml", SeedsYaml},     {"mesh", SeedsMesh}};
  for (const auto& [fuzzer, write] : writers) {
    if (name != fuzzer) continue;
    try {
      write(out);
      return 0;
    } catch (const std::exception& e) {
      std::cerr << "mocap_fuzz_seeds " << name << ": " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "mocap_fuzz_seeds: no fuzzer '" << name << "'\n";
  return 2;
}
