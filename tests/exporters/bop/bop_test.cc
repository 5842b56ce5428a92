// The BOP export read back by a reader written from the format's documentation (bop_toolkit's
// docs/bop_datasets_format.md and inout.py, formats.md §1), not from the writer's code: every file of a
// simulated session's export, and the LM-O round trip on real data.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "exporters/export/export.h"
#include "label/mask_file.h"
#include "pipeline/label_run.h"
#include "pipeline/object_library.h"
#include "session/import/bop_import.h"
#include "session/reader.h"
#include "tests/exporters/bop/export_fixture.h"

namespace mocap {
namespace {
namespace fs = std::filesystem;

nlohmann::json ReadJson(const fs::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in.good()) << file;
  return nlohmann::json::parse(in);
}

std::string Bytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string Id6(int64_t id) {
  char text[24];
  std::snprintf(text, sizeof text, "%06lld", static_cast<long long>(id));
  return text;
}

/// bop_toolkit's calc_2d_bbox over a 0/255 mask: [x, y, x_max - x, y_max - y], [-1]*4 when empty.
std::array<int, 4> Box(const cv::Mat& mask) {
  cv::Mat points;
  cv::findNonZero(mask, points);
  if (points.empty()) return {-1, -1, -1, -1};
  const cv::Rect r = cv::boundingRect(points);
  return {r.x, r.y, r.width - 1, r.height - 1};
}

/// The full-image mask the label run's packed file holds for a record (kind: amodal or visible).
cv::Mat LabelRunMask(const pipeline::LabelRunLayout& run, const pipeline::LabelRecord& r, bool visible, cv::Size size) {
  cv::Mat full = cv::Mat::zeros(size, CV_8UC1);
  if (!r.mask_rect) return full;
  const auto& b = *r.mask_rect;
  const PixelRect rect{b[0], b[1], b[2], b[3]};
  const ObjectMasks m = ReadMaskFile(run.MaskBitsPng(r.camera, r.index), rect, r.visib_source == "measured_depth", *r.mask_row);
  const std::vector<uint8_t>& bits = !visible ? m.amodal : r.visib_source == "measured_depth" ? m.visible_measured : m.visible_model;
  for (int v = 0; v < rect.height; ++v)
    for (int u = 0; u < rect.width; ++u) full.at<uint8_t>(v + rect.y, u + rect.x) = bits[static_cast<size_t>(v) * rect.width + u] ? 255 : 0;
  return full;
}

void CheckPose(const nlohmann::json& gt, const pipeline::LabelRecord& r) {
  cv::Mat R;  // OpenCV's Rodrigues, not the tool's: the rotation from the record's axis-angle
  cv::Rodrigues(cv::Vec3d(r.rvec.x(), r.rvec.y(), r.rvec.z()), R);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(gt["cam_R_m2c"][i].get<double>(), R.at<double>(i / 3, i % 3), 1e-9);  // row-major
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(gt["cam_t_m2c"][i].get<double>(), r.t_m[i] * 1000.0, 1e-9);         // mm
  EXPECT_EQ(gt["obj_id"].get<int>(), r.object);
}

TEST(BopExport, ASimulatedSessionReadsBackFileByFileFromTheFormatDocumentation) {
  const testing::LabelledSession s = testing::MakeLabelledSession("bop", 10);
  const fs::path out = s.dir / "bop";
  std::string output;
  ASSERT_EQ(testing::Mocaplabel({"export", s.session.string(), "--format", "bop", "--out", out.string(), "--split", "none"}, &output), 0) << output;
  const pipeline::LabelRun run = pipeline::LabelRun::Read(s.labels);
  const SessionReader session = SessionReader::Open(s.session);
  const pipeline::ObjectLibrary objects = pipeline::ReadObjectLibrary(s.session / "objects.yaml");

  const nlohmann::json camera = ReadJson(out / "camera.json");
  for (const char* key : {"cx", "cy", "depth_scale", "fx", "fy", "height", "width"}) EXPECT_TRUE(camera.contains(key)) << key;
  const nlohmann::json models_info = ReadJson(out / "models/models_info.json");
  for (const auto& object : objects.objects) {
    const nlohmann::json& info = models_info.at(std::to_string(object.id));
    EXPECT_GT(info["diameter"].get<double>(), 10.0) << "diameter in mm";
    EXPECT_EQ(Bytes(out / "models" / ("obj_" + Id6(object.id) + ".ply")).substr(0, 4), "ply\n");
  }
  const fs::path scene = out / "train/000001";
  const nlohmann::json scene_camera = ReadJson(scene / "scene_camera.json"), scene_gt = ReadJson(scene / "scene_gt.json"),
                       scene_gt_info = ReadJson(scene / "scene_gt_info.json");
  ASSERT_EQ(scene_gt.size(), 10u);
  const cv::Size size(camera["width"].get<int>(), camera["height"].get<int>());
  int instances = 0;
  for (const auto& [im_key, gts] : scene_gt.items()) {
    const int64_t index = std::stoll(im_key);
    const nlohmann::json& cam = scene_camera.at(im_key);
    ASSERT_EQ(cam["cam_K"].size(), 9u);
    EXPECT_EQ(cam["cam_R_w2c"].size(), 9u) << "the camera is tracked";
    EXPECT_EQ(Bytes(scene / "rgb" / (Id6(index) + ".png")), Bytes(session.ColorPath("kinect1", index))) << "recorded colour reused";
    const cv::Mat depth = cv::imread((scene / "depth" / (Id6(index) + ".png")).string(), cv::IMREAD_ANYDEPTH);
    ASSERT_EQ(depth.type(), CV_16UC1);
    const DepthImage measured_m = session.LoadDepth("kinect1", index);
    for (int v = 0; v < depth.rows; v += 7)
      for (int u = 0; u < depth.cols; u += 7)
        EXPECT_NEAR(depth.at<uint16_t>(v, u) * cam["depth_scale"].get<double>(), measured_m.at(u, v) * 1000.0, 1e-3);
    std::vector<const pipeline::LabelRecord*> records;
    for (const auto& r : run.records)
      if (r.index == index && r.has_pose) records.push_back(&r);
    ASSERT_EQ(gts.size(), records.size());
    for (size_t gt_id = 0; gt_id < gts.size(); ++gt_id, ++instances) {
      const pipeline::LabelRecord& r = *records[gt_id];
      CheckPose(gts[gt_id], r);
      const nlohmann::json& info = scene_gt_info.at(im_key)[gt_id];
      EXPECT_EQ(info["bbox_obj"].get<std::vector<int>>(), std::vector<int>(r.bbox_obj.begin(), r.bbox_obj.end()));
      EXPECT_EQ(info["px_count_all"].get<int64_t>(), r.px_count_all);
      EXPECT_EQ(info["px_count_visib"].get<int64_t>(), r.px_count_visib);
      EXPECT_EQ(info["px_count_valid"].get<int64_t>(), r.px_count_valid.value_or(0));
      EXPECT_DOUBLE_EQ(info["visib_fract"].get<double>(), r.visib_fract);
      const std::string name = Id6(index) + "_" + Id6(static_cast<int64_t>(gt_id)) + ".png";
      const cv::Mat mask = cv::imread((scene / "mask" / name).string(), cv::IMREAD_UNCHANGED);
      const cv::Mat visib = cv::imread((scene / "mask_visib" / name).string(), cv::IMREAD_UNCHANGED);
      ASSERT_EQ(mask.type(), CV_8UC1);
      EXPECT_EQ(cv::countNonZero(mask != LabelRunMask(run.layout, r, false, size)), 0) << name;
      EXPECT_EQ(cv::countNonZero(visib != LabelRunMask(run.layout, r, true, size)), 0) << name;
      // calc_gt_info's statistics from the files themselves.
      EXPECT_EQ(cv::countNonZero(visib), r.px_count_visib) << name;
      EXPECT_LE(cv::countNonZero(mask), r.px_count_all) << name;
      const auto box = Box(visib);
      EXPECT_EQ(info["bbox_visib"].get<std::vector<int>>(), std::vector<int>(box.begin(), box.end())) << name;
    }
  }
  EXPECT_GE(instances, 30);
  const nlohmann::json targets = ReadJson(out / "test_targets_bop19.json");
  EXPECT_FALSE(targets.empty());
  EXPECT_EQ(ReadJson(out / "run.json")["kind"], "export");
  fs::remove_all(s.dir);
}

/// LM-O: `import bop`, `label`, `export --format bop` gives back the original scene_gt and (within the
/// renderer's conventions) scene_gt_info.
TEST(BopExport, LmoRoundTripGivesBackTheOriginalGroundTruth) {
  const fs::path lmo = fs::path(MOCAP_SHARED_DIR) / "realdata/bop_lmo_scene2";
  const fs::path dir = fs::temp_directory_path() / ("mocaplabel_export_lmo_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  std::string output;
  ASSERT_EQ(testing::Mocaplabel({"import", "bop", (lmo / "test/000002").string(), "--models", (lmo / "models").string(),
                                 "--out", (dir / "S").string()}, &output), 0) << output;
  ASSERT_EQ(testing::Mocaplabel({"label", (dir / "S").string()}, &output), 0) << output;
  ASSERT_EQ(testing::Mocaplabel({"export", (dir / "S").string(), "--format", "bop", "--out", (dir / "D").string(),
                                 "--split", "none", "--no-models"}, &output), 0) << output;
  const nlohmann::json original_gt = ReadJson(lmo / "test/000002/scene_gt.json");
  const nlohmann::json original_info = ReadJson(lmo / "test/000002/scene_gt_info.json");
  const nlohmann::json gt = ReadJson(dir / "D/train/000001/scene_gt.json"), info = ReadJson(dir / "D/train/000001/scene_gt_info.json");
  // Our im_id is the session's frame index; the import keeps the original im_id as each frame's source id.
  const pipeline::LabelRun run = pipeline::LabelRun::Read(dir / "S/labels");
  std::map<int64_t, std::string> source_of_index;
  for (const auto& r : run.records) source_of_index[r.index] = r.source_id;
  ASSERT_EQ(gt.size(), 10u) << "the ten images the scene folder holds";
  int compared = 0;
  double worst_box_px = 0, worst_count_fraction = 0, worst_raw_r = 0;
  for (const auto& [im_key, gts] : gt.items()) {
    const std::string original_key = source_of_index.at(std::stoll(im_key));
    const nlohmann::json& expected = original_gt.at(original_key);
    ASSERT_EQ(gts.size(), expected.size()) << original_key;
    for (size_t k = 0; k < gts.size(); ++k) {  // same order: the import made one body per gt entry, in order
      EXPECT_EQ(gts[k]["obj_id"], expected[k]["obj_id"]);
      // LM-O's matrices are rounded to 8 digits and not orthonormal (|R R^T - I| up to 2e-3): no rotation
      // equals them to 1e-6. What a rotation can match is the nearest one (SVD polar factor).
      const Eigen::Matrix3d original = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
          expected[k]["cam_R_m2c"].get<std::vector<double>>().data());
      const Eigen::JacobiSVD<Eigen::Matrix3d> svd(original, Eigen::ComputeFullU | Eigen::ComputeFullV);
      const Eigen::Matrix3d nearest = svd.matrixU() * svd.matrixV().transpose();
      for (int i = 0; i < 9; ++i) {
        EXPECT_NEAR(gts[k]["cam_R_m2c"][i].get<double>(), nearest(i / 3, i % 3), 1e-6);
        worst_raw_r = std::max(worst_raw_r, std::abs(gts[k]["cam_R_m2c"][i].get<double>() - original(i / 3, i % 3)));
      }
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(gts[k]["cam_t_m2c"][i].get<double>(), expected[k]["cam_t_m2c"][i].get<double>(), 1e-3);
      const nlohmann::json &a = info.at(im_key)[k], &b = original_info.at(original_key)[k];
      for (int i = 0; i < 4; ++i)
        worst_box_px = std::max(worst_box_px, std::abs(a["bbox_obj"][i].get<double>() - b["bbox_obj"][i].get<double>()));
      const double all = b["px_count_all"];
      worst_count_fraction = std::max(worst_count_fraction, std::abs(a["px_count_all"].get<double>() - all) / all);
      ++compared;
    }
  }
  EXPECT_GT(compared, 50);
  RecordProperty("worst_bbox_obj_px", std::to_string(worst_box_px));
  RecordProperty("worst_px_count_all_fraction", std::to_string(worst_count_fraction));
  std::printf("LM-O round trip: %d instances, R within %.1e of the file's (non-orthonormal) matrices, bbox_obj within "
              "%.0f px, px_count_all within %.2f %%\n", compared, worst_raw_r, worst_box_px, 100 * worst_count_fraction);
  EXPECT_LE(worst_box_px, 1.0);
  EXPECT_LE(worst_count_fraction, 0.015);  // 1.24 % measured: the renderer's rasterisation against BOP's
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mocap
