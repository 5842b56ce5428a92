#pragma once
// A tiny synthetic rig written as a real session: a camera on a tracked body looking at one tracked
// object, with every transform known, so label outputs can be checked against hand-composed poses.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "label/mask_file.h"
#include "session/writer.h"

namespace mocap::testing {

inline constexpr int64_t kMs = 1'000'000;

inline PinholeCamera TestCamera() {
  return {.width = 320, .height = 240, .fx = 300, .fy = 300, .cx = 159.5, .cy = 119.5};
}

/// A 6 mm square (two triangles) centred on `centre_m` in the mesh frame, facing -z, as an OBJ file.
inline void WriteMarkerSquareObj(const std::filesystem::path& path, const Eigen::Vector3d& centre_m, double scale) {
  std::ofstream out(path);
  const double h = 0.003;
  for (const auto& [dx, dy] : std::vector<std::pair<double, double>>{{-h, -h}, {h, -h}, {h, h}, {-h, h}})
    out << "v " << (centre_m.x() + dx) / scale << ' ' << (centre_m.y() + dy) / scale << ' ' << centre_m.z() / scale << '\n';
  out << "f 1 2 3\nf 1 3 4\n";
}

struct SyntheticRig {
  Rigid3d T_tracker_cambody = Rigid3d::FromRvec({0.1, -0.05, 0.2}, {0.3, -0.2, 1.5});
  Rigid3d T_cambody_camera = Rigid3d::FromRvec({0.02, 0.3, -0.1}, {0.05, 0.01, -0.02});
  Rigid3d T_objbody_mesh = Rigid3d::FromRvec({-0.2, 0.1, 0.4}, {0.01, -0.03, 0.02});
  /// Placed so the mesh origin sits 0.8 m in front of the camera.
  Rigid3d T_camera_mesh = Rigid3d::FromRvec({0.3, -0.2, 0.25}, {0.02, -0.01, 0.8});
  /// Tracker body names: user-chosen text (a TUM import calls its camera body "camera").
  std::string cambody = "cambody", objbody = "objbody";
  bool with_camera = true;  ///< false: a tracker-only session (a Motive or PLUS import)

  Rigid3d T_tracker_objbody() const {
    return T_tracker_cambody * T_cambody_camera * T_camera_mesh * T_objbody_mesh.inverse();
  }

  /// Writes `frames` camera frames at 30 Hz and 100 Hz tracker samples of both bodies. Object samples
  /// in [dropout_begin_ns, dropout_end_ns) are written as missing.
  /// `depth`: the 16-bit depth image (mm) of every frame, registered to colour; empty = none.
  void WriteSession(const std::filesystem::path& dir, int frames, int64_t dropout_begin_ns = -1,
                    int64_t dropout_end_ns = -1, const cv::Mat& depth = cv::Mat()) const {
    SessionManifest manifest;
    manifest.source = "test";
    CameraStreamInfo cam;
    cam.name = "cam";
    cam.model = "sim";
    cam.color_camera = cam.depth_camera = TestCamera();
    cam.camera_body = cambody;
    cam.T_body_camera = T_cambody_camera;
    if (with_camera) manifest.cameras.push_back(cam);
    manifest.trackers.push_back({"ndi", "sim", "", "tracker", {cambody, objbody}});
    auto writer = SessionWriter::Create(dir, manifest);
    const int64_t end_ns = frames * 33 * kMs + 50 * kMs;
    for (int64_t t = 0; t <= end_ns; t += 10 * kMs) {
      writer->WriteTrackerSample("ndi", {cambody, PoseStatus::kValid, t / (10 * kMs), 0, t, T_tracker_cambody, 0, 0});
      const bool lost = t >= dropout_begin_ns && t < dropout_end_ns;
      writer->WriteTrackerSample(
          "ndi", {objbody, lost ? PoseStatus::kMissing : PoseStatus::kValid, t / (10 * kMs), 0, t, T_tracker_objbody(), 0, 0});
    }
    const cv::Mat color(TestCamera().height, TestCamera().width, CV_8UC3, cv::Scalar(40, 40, 40));
    for (int i = 0; with_camera && i < frames; ++i) {
      CameraFrameRecord record;
      record.frame = i;
      record.stamp_ns = 20 * kMs + i * 33 * kMs;
      writer->WriteCameraFrame("cam", record, color, depth);
    }
    writer->Close();
  }
};

inline std::vector<nlohmann::json> ReadJsonLines(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

/// Compares one mask recovered from the packed file with the full-size 0/255 PNG at `full_png`.
inline void ExpectSameMask(const std::vector<uint8_t>& mask, const PixelRect& rect, const std::filesystem::path& full_png) {
  const cv::Mat full = cv::imread(full_png.string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(full.empty()) << full_png;
  const Image<uint8_t> recovered = ToFullImage(mask, rect, full.cols, full.rows);
  ASSERT_TRUE(full.isContinuous());
  EXPECT_TRUE(std::equal(recovered.data.begin(), recovered.data.end(), full.ptr<uint8_t>(0))) << full_png;
}

/// Every record with a mask: the three masks of its packed file equal the BOP-style files.
inline int CheckPackedMasks(const std::filesystem::path& labels, const std::vector<nlohmann::json>& records) {
  int checked = 0;
  for (const auto& r : records) {
    if (!r.contains("mask_rect") || r["mask_rect"].is_null()) continue;
    const auto& m = r["mask_rect"];
    const PixelRect rect{m[0], m[1], m[2], m[3]};
    char stem[32], frame[32];
    std::snprintf(stem, sizeof(stem), "%06d_%06d.png", r["index"].get<int>(), r["instance"].get<int>());
    std::snprintf(frame, sizeof(frame), "%06d.png", r["index"].get<int>());
    const auto camera = labels / r["camera"].get<std::string>();
    const ObjectMasks masks =
        ReadMaskFile(camera / "mask_bits" / frame, rect, r["visib_source"] == "measured_depth", r["mask_row"].get<int>());
    ExpectSameMask(masks.amodal, rect, camera / "mask" / stem);
    ExpectSameMask(masks.visible_model, rect, camera / "mask_visib" / stem);
    if (!masks.visible_measured.empty()) ExpectSameMask(masks.visible_measured, rect, camera / "mask_visib_depth" / stem);
    ++checked;
  }
  return checked;
}

inline std::filesystem::path FreshDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("mocaplabel_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace mocap::testing
