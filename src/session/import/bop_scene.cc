#include "session/import/bop_scene.h"

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "core/check.h"
#include "core/text.h"
#include "session/import/text_parse.h"

namespace mocap::import {
namespace {

using nlohmann::json;

// LM-O's manually refined ground truth has |R R^T - I| up to 0.016 (median 4e-4); such matrices are
// projected onto the nearest rotation. A scaled or transposed-with-translation matrix is far beyond.
constexpr double kRotationTolerance = 0.05;

json ReadJson(const std::filesystem::path& file) {
  const std::string text = ReadTextFile(file);
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(Str(file.string(), ": byte ", e.byte), Str("invalid JSON: ", QuoteForMessage(e.what(), 200)));
  } catch (const json::exception& e) {  // a number beyond double's range (out_of_range.406), found by tests/fuzz
    throw InputError(file.string(), Str("invalid JSON: ", QuoteForMessage(e.what(), 200)));
  }
}

const json& Member(const json& object, const std::string& key, const std::string& where) {
  if (!object.is_object() || !object.contains(key)) throw InputError(where, Str("missing \"", key, "\""));
  return object.at(key);
}

std::vector<double> Numbers(const json& value, size_t count, const std::string& where) {
  if (!value.is_array() || value.size() != count)
    throw InputError(where, Str("expected an array of ", count, " numbers"));
  std::vector<double> out;
  for (const auto& v : value) {
    if (!v.is_number()) throw InputError(where, Str(QuoteForMessage(v.dump()), " is not a number"));
    out.push_back(v.get<double>());
  }
  return out;
}

int ImageId(const std::string& key, const std::string& where) {
  const int64_t id = ParseInt(key, where);
  if (id < 0 || id > 10'000'000) throw InputError(where, Str("im_id ", id, " out of range"));
  return static_cast<int>(id);
}

std::string Padded(int id) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d", id);
  return name;
}

// Width and height from a PNG's IHDR chunk (bytes 16..23, big-endian); empty when not a PNG.
std::optional<std::pair<int, int>> PngSize(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  unsigned char b[24] = {};
  if (!in.read(reinterpret_cast<char*>(b), 24) || b[1] != 'P' || b[2] != 'N' || b[3] != 'G') return std::nullopt;
  auto be32 = [&](int at) {
    return static_cast<int>((uint32_t{b[at]} << 24) | (uint32_t{b[at + 1]} << 16) | (uint32_t{b[at + 2]} << 8) | b[at + 3]);
  };
  return std::pair{be32(16), be32(20)};
}

std::pair<int, int> ImageSize(const BopScene& scene, const std::filesystem::path& scene_dir) {
  if (!scene.frames.empty())
    if (auto size = PngSize(scene.frames.front().rgb)) return *size;
  const auto camera_json = scene_dir.parent_path().parent_path() / "camera.json";
  if (std::filesystem::exists(camera_json)) {
    const json cam = ReadJson(camera_json);
    return {Member(cam, "width", camera_json.string()).get<int>(), Member(cam, "height", camera_json.string()).get<int>()};
  }
  throw InputError(scene_dir.string(), "cannot tell the image size (no PNG colour image and no ../../camera.json)");
}

PinholeCamera CameraFromK(const json& entry, const std::string& where) {
  const auto K = Numbers(Member(entry, "cam_K", where), 9, where + " cam_K");
  if (K[1] != 0 || K[3] != 0 || K[6] != 0 || K[7] != 0 || K[8] != 1)
    throw InputError(where + " cam_K", "not a pinhole matrix [fx 0 cx; 0 fy cy; 0 0 1] (skew is not supported)");
  if (!(K[0] > 0) || !(K[4] > 0) || !std::isfinite(K[0]) || !std::isfinite(K[4]) || !std::isfinite(K[2]) ||
      !std::isfinite(K[5]))
    throw InputError(where + " cam_K", Str("focal lengths must be positive and all entries finite (fx ", K[0], ", fy ", K[4], ")"));
  PinholeCamera camera;
  camera.fx = K[0];
  camera.cx = K[2];
  camera.fy = K[4];
  camera.cy = K[5];
  return camera;
}

// Depth units in mm per stored unit; checked here so the error names the file and image.
double DepthScale(const json& value, const std::string& where) {
  const double scale = Numbers(json::array({value}), 1, where)[0];
  if (!(scale > 0) || !std::isfinite(scale)) throw InputError(where, Str("must be a positive number of mm per depth unit, got ", scale));
  return scale;
}

std::filesystem::path FindImage(const std::filesystem::path& folder, int im_id) {
  for (const char* ext : {".png", ".jpg", ".jpeg"}) {
    auto path = folder / (Padded(im_id) + ext);
    if (std::filesystem::is_regular_file(path)) return std::filesystem::absolute(path).lexically_normal();
  }
  return {};
}

std::vector<BopObjectPose> ReadObjects(const json& list, const std::string& where) {
  if (!list.is_array()) throw InputError(where, "expected a list of object annotations");
  std::vector<BopObjectPose> objects;
  std::map<int, int> instances;
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string at = Str(where, "[", k, "]");
    BopObjectPose pose;
    const auto& id = Member(list[k], "obj_id", at);
    if (!id.is_number_integer() || id.get<int>() <= 0) throw InputError(at, "obj_id must be a positive integer");
    pose.obj_id = id.get<int>();
    pose.instance = instances[pose.obj_id]++;
    pose.gt_index = static_cast<int>(k);
    const auto R = Numbers(Member(list[k], "cam_R_m2c", at), 9, at + " cam_R_m2c");
    const auto t = Numbers(Member(list[k], "cam_t_m2c", at), 3, at + " cam_t_m2c");
    const Eigen::Matrix3d M = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R.data());
    pose.T_camera_object = Rigid3d(RotationFromNearlyOrthonormal(M, at + " cam_R_m2c", kRotationTolerance),
                                   Eigen::Vector3d(t[0], t[1], t[2]) * 1e-3);  // BOP: mm
    objects.push_back(pose);
  }
  return objects;
}

std::vector<BopModel> ReadModels(const std::filesystem::path& models_dir) {
  const auto info_file = models_dir / "models_info.json";
  const json info = ReadJson(info_file);
  if (!info.is_object()) throw InputError(info_file.string(), "expected an object keyed by obj_id");
  std::vector<BopModel> models;
  for (const auto& [key, entry] : info.items()) {
    const std::string where = Str(info_file.string(), ": key ", QuoteForMessage(key));
    BopModel model;
    model.obj_id = static_cast<int>(ParseInt(key, where));
    const double diameter_mm = Numbers(json::array({Member(entry, "diameter", where)}), 1, where + " diameter")[0];
    // Models in metres are the most common BOP mistake: a real object is over a millimetre across.
    if (diameter_mm < 1.0)
      throw InputError(where, Str("diameter ", diameter_mm, " looks like metres; BOP models are in mm"));
    model.diameter_m = diameter_mm * 1e-3;
    model.mesh = std::filesystem::absolute(models_dir / ("obj_" + Padded(model.obj_id) + ".ply")).lexically_normal();
    model.mesh_exists = std::filesystem::is_regular_file(model.mesh);
    models.push_back(model);
  }
  std::sort(models.begin(), models.end(), [](const auto& a, const auto& b) { return a.obj_id < b.obj_id; });
  return models;
}

void CheckMillimetres(const BopScene& scene, const std::filesystem::path& gt_file) {
  std::vector<double> z_m;
  for (const auto& frame : scene.frames)
    for (const auto& object : frame.objects) z_m.push_back(std::abs(object.T_camera_object.translation().z()));
  if (z_m.empty()) return;
  std::nth_element(z_m.begin(), z_m.begin() + static_cast<long>(z_m.size() / 2), z_m.end());
  // Objects a centimetre from the lens cannot be seen; a median that close means metres were written.
  if (z_m[z_m.size() / 2] < 0.01)
    throw InputError(gt_file.string(), Str("median cam_t_m2c z is ", z_m[z_m.size() / 2] * 1e3,
                                           " units; BOP translations are in mm (were metres written?)"));
}

}  // namespace

std::string BopObjectName(int obj_id) { return "obj_" + Padded(obj_id); }

BopScene ReadBopScene(const std::filesystem::path& scene_dir, const std::filesystem::path& models_dir) {
  if (!std::filesystem::is_directory(scene_dir)) throw InputError(scene_dir.string(), "not a folder (expected a BOP scene)");
  BopScene scene;
  scene.dir = std::filesystem::absolute(scene_dir).lexically_normal();
  const std::string folder = scene.dir.lexically_normal().filename().string().empty()
                                 ? scene.dir.lexically_normal().parent_path().filename().string()
                                 : scene.dir.lexically_normal().filename().string();
  if (!folder.empty() && std::all_of(folder.begin(), folder.end(), ::isdigit)) scene.scene_id = std::stoi(folder);
  scene.models = ReadModels(models_dir);
  const auto camera_file = scene_dir / "scene_camera.json";
  const auto gt_file = scene_dir / "scene_gt.json";
  const json cameras = ReadJson(camera_file);
  const json gt = ReadJson(gt_file);
  if (!gt.is_object()) throw InputError(gt_file.string(), "expected an object keyed by im_id");
  std::map<int, std::string> keys;  // numeric order, not JSON's string order
  for (const auto& [key, value] : gt.items()) keys[ImageId(key, Str(gt_file.string(), ": key ", QuoteForMessage(key)))] = key;
  scene.annotated_frames = static_cast<int>(keys.size());
  for (const auto& [im_id, key] : keys) {
    BopFrame frame;
    frame.im_id = im_id;
    frame.rgb = FindImage(scene_dir / "rgb", im_id);
    if (frame.rgb.empty()) {
      ++scene.frames_without_rgb;
      continue;
    }
    frame.depth = FindImage(scene_dir / "depth", im_id);
    const std::string cam_where = Str(camera_file.string(), ": \"", key, "\"");
    const json& cam = Member(cameras, key, camera_file.string());
    frame.camera = CameraFromK(cam, cam_where);
    if (cam.contains("depth_scale")) frame.depth_scale_mm = DepthScale(cam["depth_scale"], cam_where + " depth_scale");
    else if (!frame.depth.empty()) throw InputError(cam_where, "missing \"depth_scale\" for a frame with depth");
    frame.objects = ReadObjects(gt.at(key), Str(gt_file.string(), ": \"", key, "\""));
    for (const auto& object : frame.objects)
      if (std::none_of(scene.models.begin(), scene.models.end(), [&](const auto& m) { return m.obj_id == object.obj_id; }))
        throw InputError(Str(gt_file.string(), ": \"", key, "\""), Str("obj_id ", object.obj_id, " is not in models_info.json"));
    scene.frames.push_back(std::move(frame));
  }
  const auto [width, height] = ImageSize(scene, scene_dir);
  for (auto& frame : scene.frames) {
    frame.camera.width = width;
    frame.camera.height = height;
    frame.camera.check();
  }
  CheckMillimetres(scene, gt_file);
  return scene;
}

}  // namespace mocap::import
