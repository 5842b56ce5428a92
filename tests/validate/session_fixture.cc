#include "session_fixture.h"

#include <unistd.h>

#include <fstream>
#include <random>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "label/labeller.h"
#include "tests/pipeline/label_run_testing.h"
#include "session/image_io.h"
#include "session/import/bop_import.h"

namespace mocap::testing {
namespace {

namespace fs = std::filesystem;
const fs::path kBop = fs::path(MOCAP_SHARED_DIR) / "realdata/bop_lmo_scene2";

std::vector<nlohmann::json> ReadLines(const fs::path& file) {
  std::ifstream in(file);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

/// The label run's rendered depth of frame `stem` with Kinect1 noise, as a 16-bit PNG in millimetres.
void WriteNoisyDepth(const fs::path& exr, const fs::path& png, std::mt19937& rng) {
  const DepthImage rendered = ReadDepth(exr, 1.0);
  std::normal_distribution<double> unit(0.0, 1.0);
  cv::Mat mm(rendered.height, rendered.width, CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < rendered.height; ++v)
    for (int u = 0; u < rendered.width; ++u) {
      const double z = rendered.at(u, v);
      if (z <= 0) continue;
      const double noisy = z + 1.425e-3 * z * z * unit(rng);
      mm.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(noisy * 1e3));
    }
  cv::imwrite(png.string(), mm);
}

/// The labeller's run over the imported scene without depth (`dir`/S_rgb) with `objects`, into `out_dir`.
void LabelRgbSession(const fs::path& dir, const std::vector<LabelObject>& objects, const fs::path& out_dir) {
  LabelRunOptions label;
  label.out_dir = out_dir;
  label.threads = 2;
  label.output.write_overlay = true;
  label.output.write_masks = false;
  LabelSession(SessionReader::Open(dir / "S_rgb"), objects, LabelRig{}, label);
}

}  // namespace

fs::path FreshTempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::vector<ValidationObject> SessionObjects(const fs::path& session_dir) {
  return ReadValidationObjects(session_dir / "objects.yaml");
}

BopDepthScene MakeBopDepthScene(const fs::path& dir, const std::vector<int64_t>& frames_without_depth, uint32_t seed) {
  import::ImportBop(kBop / "test/000002", kBop / "models", dir / "S_rgb", BopOptions());
  LabelRgbSession(dir, ReadLabelObjects(dir / "S_rgb" / "objects.yaml"), dir / "L");

  // A BOP scene folder with the same images, JSON files and the noisy depth.
  const fs::path scene = dir / "scene";
  fs::create_directories(scene / "rgb");
  fs::create_directories(scene / "depth");
  for (const char* json : {"scene_camera.json", "scene_gt.json", "scene_gt_info.json"})
    fs::copy_file(kBop / "test/000002" / json, scene / json);
  std::mt19937 rng(seed);
  for (const nlohmann::json& r : ReadLines(dir / "L" / "labels.jsonl")) {
    const int64_t index = r["index"];
    char stem[16], im[16];
    std::snprintf(stem, sizeof stem, "%06lld", static_cast<long long>(index));
    std::snprintf(im, sizeof im, "%06d", std::stoi(r["source_id"].get<std::string>()));
    const fs::path rgb = scene / "rgb" / (std::string(im) + ".png");
    if (fs::exists(rgb)) continue;  // one record per frame is enough
    fs::create_symlink(kBop / "test/000002/rgb" / (std::string(im) + ".png"), rgb);
    if (std::find(frames_without_depth.begin(), frames_without_depth.end(), index) != frames_without_depth.end())
      continue;
    WriteNoisyDepth(dir / "L" / "bop" / "depth" / (std::string(stem) + ".exr"), scene / "depth" / (std::string(im) + ".png"), rng);
  }
  import::ImportBop(scene, kBop / "models", dir / "S", BopOptions());
  return {dir / "S", dir / "L", SessionObjects(dir / "S")};
}

sim::CalibrationErrors ObjectMountErrors(const std::vector<std::string>& objects, double translation_m, double angle_deg,
                                         uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  sim::CalibrationErrors errors;
  for (const std::string& object : objects) {
    const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    errors.object_mounts.push_back({object, dir * translation_m, axis * angle_deg});
  }
  return errors;
}

fs::path LabelWithMountErrors(const fs::path& dir, const std::string& name, double translation_m, double angle_deg,
                              uint32_t seed) {
  std::vector<LabelObject> objects = ReadLabelObjects(dir / "S_rgb" / "objects.yaml");
  std::vector<std::string> names;
  for (const LabelObject& object : objects) names.push_back(object.name);
  const sim::CalibrationErrors errors = ObjectMountErrors(names, translation_m, angle_deg, seed);
  for (size_t i = 0; i < objects.size(); ++i) {
    const auto& e = errors.object_mounts[i];
    for (BodyMount& mount : objects[i].mounts)
      mount.T_body_mesh = mount.T_body_mesh * Rigid3d::FromRvec(e.rotation_deg * (M_PI / 180.0), e.translation_m);
  }
  const fs::path out = dir / ("L_" + name);
  LabelRgbSession(dir, objects, out);
  return out;
}

Rates ComputeRates(const SessionValidation& validation) {
  Rates rates;
  int64_t accepted = 0, success = 0;
  for (const RecordCheck& r : validation.records) {
    if (IsBadInput(r.check.reason_code)) continue;
    ++rates.checked;
    accepted += r.check.verdict == Verdict::kAccept;
    success += r.check.success;
  }
  if (rates.checked == 0) return rates;
  rates.accepted = static_cast<double>(accepted) / rates.checked;
  rates.flagged = 1.0 - rates.accepted;
  rates.success = static_cast<double>(success) / rates.checked;
  return rates;
}

}  // namespace mocap::testing
