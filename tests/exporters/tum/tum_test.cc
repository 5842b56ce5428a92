// The TUM exporter: stamps and pose lines worked out by hand; the layout and the TUM file rules ('#'
// comments, 2 or 8 fields, sorted stamps, listed files present) on an in-memory dataset; and a simulated
// session, labelled, exported and read back by the project's TUM importer (session/import/tum_import.h):
// same stamps, camera poses to 1e-9 m / 1e-9 rad, depth within TUM's 1/5000 m quantisation, colour bytes.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "core/check.h"
#include "exporters/dataset/selection.h"
#include "exporters/tum/tum_writer.h"
#include "pipeline/label_stage.h"
#include "pipeline/record_stage.h"
#include "session/import/tum_import.h"
#include "tests/exporters/simulated_labels.h"
#include "tests/labeller/labeller_test_util.h"

namespace mocap::exporters {
namespace {

namespace fs = std::filesystem;

std::string ReadText(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The data lines of a TUM text file, split into fields; every other line must be a '#' comment.
std::vector<std::vector<std::string>> DataLines(const fs::path& file) {
  std::vector<std::vector<std::string>> lines;
  std::istringstream in(ReadText(file));
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> f;
    for (std::string field; fields >> field;) f.push_back(field);
    EXPECT_FALSE(f.empty()) << file << ": blank line";
    lines.push_back(f);
  }
  return lines;
}

/// What TUM's tools assume of a sequence folder: list lines "timestamp filename" with the file present,
/// trajectory lines of 8 numbers with a unit quaternion, stamps ascending (associate.py reads floats).
void ExpectTumFiles(const fs::path& seq) {
  for (const char* list : {"rgb.txt", "depth.txt"}) {
    double last = -1e300;
    for (const auto& f : DataLines(seq / list)) {
      ASSERT_EQ(f.size(), 2u) << list;
      EXPECT_GE(std::stod(f[0]), last);
      last = std::stod(f[0]);
      EXPECT_TRUE(fs::is_regular_file(seq / f[1])) << f[1];
    }
  }
  std::vector<fs::path> trajectories = {seq / "groundtruth.txt"};
  if (fs::is_directory(seq / "objects"))
    for (const auto& e : fs::directory_iterator(seq / "objects")) trajectories.push_back(e.path());
  for (const fs::path& file : trajectories) {
    EXPECT_EQ(ReadText(file).substr(0, 2), "# ") << file;
    for (const auto& f : DataLines(file)) {
      ASSERT_EQ(f.size(), 8u) << file;
      const double qx = std::stod(f[4]), qy = std::stod(f[5]), qz = std::stod(f[6]), qw = std::stod(f[7]);
      EXPECT_NEAR(qx * qx + qy * qy + qz * qz + qw * qw, 1.0, 1e-10);
      EXPECT_GE(qw, 0.0);
    }
  }
}

TEST(TumText, StampsAreExactSecondsWithNineDecimals) {
  EXPECT_EQ(TumStampText(1305031102175304000), "1305031102.175304000");
  EXPECT_EQ(TumStampText(0), "0.000000000");
  EXPECT_EQ(TumStampText(5), "0.000000005");
  EXPECT_EQ(TumStampText(28160340930110), "28160.340930110");
  EXPECT_EQ(TumStampText(-1'500'000'000), "-1.500000000");
}

TEST(TumText, PoseLineIsTranslationThenScalarLastQuaternion) {
  // 90 degrees about z: q = (x, y, z, w) = (0, 0, sin 45, cos 45).
  const Rigid3d T = Rigid3d::FromQuatWxyz(std::sqrt(0.5), 0, 0, std::sqrt(0.5), {1.5, -0.25, 2});
  EXPECT_EQ(TumPoseLine(1'000'000'001, T),
            "1.000000001 1.500000000 -0.250000000 2.000000000 0.000000000000 0.000000000000 0.707106781187 0.707106781187");
  // The sign is fixed (qw >= 0), so the same rotation always prints the same line.
  EXPECT_EQ(TumPoseLine(0, Rigid3d::FromQuatWxyz(-std::sqrt(0.5), 0, 0, -std::sqrt(0.5), {0, 0, 0})).substr(40),
            TumPoseLine(0, Rigid3d::FromQuatWxyz(std::sqrt(0.5), 0, 0, std::sqrt(0.5), {0, 0, 0})).substr(40));
}

/// One scene with three frames (stamps out of order on purpose), colour only, two instances of one
/// object and one of another; the camera tracked in all but the last frame.
Dataset InMemoryDataset(const fs::path& dir, bool tracked) {
  Dataset d;
  pipeline::LibraryObject mug, can;
  mug.id = 7, mug.name = "mug", mug.object_class = "cup";
  can.id = 2, can.name = "soup can", can.object_class = "can";
  d.objects.objects = {mug, can};
  ExportScene& scene = d.scenes.emplace_back();
  scene.scene_id = 3, scene.name = "S/cam", scene.camera = "cam", scene.color_camera = testing::TestCamera();
  cv::imwrite((dir / "c.png").string(), cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3)));
  const int64_t stamps[] = {2'000'000'000, 1'000'000'000, 3'000'000'000};
  for (int i = 0; i < 3; ++i) {
    ExportFrame& f = d.frames.emplace_back();
    f.index = i, f.frame = i, f.stamp_ns = stamps[i], f.im_id = i, f.color_path = dir / "c.png", f.split = "train";
    if (tracked && i < 2) f.T_tracker_camera = Rigid3d::FromRvec({0, 0, 0.1 * i}, {i * 1.0, 0, 0});
    for (auto [object, instance] : {std::pair{7, 1}, {7, 2}, {2, 3}}) {
      ExportInstance& e = f.instances.emplace_back();
      e.record.object = object, e.record.instance = instance, e.record.has_pose = true;
      e.record.rvec = {0.2, 0, 0}, e.record.t_m = {0, 0, 1.0 + instance};
    }
  }
  return d;
}

TEST(TumWriter, InMemoryDatasetLayoutAndObjectTrajectories) {
  const fs::path dir = testing::FreshDir("tum_memory");
  const Dataset d = InMemoryDataset(dir, true);
  const WriteSummary s = WriteTum(d, dir / "out", TumExportOptions{.threads = 2});
  const fs::path seq = dir / "out/train/000003";
  ExpectTumFiles(seq);
  EXPECT_EQ(s.images, 3);
  EXPECT_EQ(s.annotations, 6);  // 3 instances in each of the 2 tracked frames
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("1 frames without a camera pose"), std::string::npos);
  const auto rgb = DataLines(seq / "rgb.txt");
  ASSERT_EQ(rgb.size(), 3u);  // sorted by stamp
  EXPECT_EQ(rgb[0], (std::vector<std::string>{"1.000000000", "rgb/1.000000000.png"}));
  EXPECT_EQ(rgb[2][0], "3.000000000");
  EXPECT_TRUE(DataLines(seq / "depth.txt").empty());  // the frames have no depth
  const auto gt = DataLines(seq / "groundtruth.txt");
  ASSERT_EQ(gt.size(), 2u);
  EXPECT_EQ(gt[0][0], "1.000000000");
  EXPECT_EQ(gt[0][1], "1.000000000");  // frame 1 is 1 m along x
  for (const char* name : {"mug_1.txt", "mug_2.txt", "soup_can.txt"}) EXPECT_TRUE(fs::exists(seq / "objects" / name)) << name;
  // T_tracker_mesh = T_tracker_camera * T_camera_mesh, read back by the importer's own parser.
  const auto mug2 = import::ReadTumGroundTruth(seq / "objects/mug_2.txt");
  ASSERT_EQ(mug2.samples.size(), 2u);
  const Rigid3d expected = *d.frames[1].T_tracker_camera * d.frames[1].instances[1].record.T_camera_mesh();
  EXPECT_LT(TranslationDistanceM(mug2.samples[0].pose, expected), 1e-9);
  EXPECT_LT(RotationDistanceDeg(mug2.samples[0].pose, expected), 1e-8);
  EXPECT_NE(ReadText(seq / "camera.txt").find("\n320 240 300 300 159.5 119.5 0 0 0 0 0 0 0 0\n"), std::string::npos)
      << ReadText(seq / "camera.txt");
}

TEST(TumWriter, JpegToPngReencodesAndATruncatedJpegIsAnErrorNamingTheFile) {
  const fs::path dir = testing::FreshDir("tum_jpeg");
  Dataset d = InMemoryDataset(dir, true);
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", cv::Mat(4, 4, CV_8UC3, cv::Scalar(40, 80, 120)), jpeg);
  const auto write = [](const fs::path& path, const std::vector<uint8_t>& bytes, size_t size) {
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(size));
  };
  write(dir / "c.jpg", jpeg, jpeg.size());
  for (ExportFrame& f : d.frames) f.color_path = dir / "c.jpg";
  WriteTum(d, dir / "whole", TumExportOptions{.jpeg_to_png = true});
  const cv::Mat png = cv::imread((dir / "whole/train/000003/rgb/1.000000000.png").string(), cv::IMREAD_COLOR);
  ASSERT_FALSE(png.empty());
  EXPECT_NEAR(png.at<cv::Vec3b>(1, 1)[2], 120, 4);
  write(dir / "c.jpg", jpeg, jpeg.size() / 2);
  try {
    WriteTum(d, dir / "cut", TumExportOptions{.jpeg_to_png = true});
    FAIL() << "a truncated JPEG was exported";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("c.jpg"), std::string::npos) << e.what();
  }
}

TEST(TumWriter, UntrackedCameraIsAnErrorUnlessCameraFrameIsAsked) {
  const fs::path dir = testing::FreshDir("tum_untracked");
  const Dataset d = InMemoryDataset(dir, false);
  EXPECT_THROW(WriteTum(d, dir / "a"), InputError);
  const WriteSummary s = WriteTum(d, dir / "b", TumExportOptions{.camera_frame_when_untracked = true});
  const fs::path seq = dir / "b/train/000003";
  ExpectTumFiles(seq);
  EXPECT_TRUE(DataLines(seq / "groundtruth.txt").empty());
  EXPECT_FALSE(fs::exists(seq / "objects"));
  const auto can = import::ReadTumGroundTruth(seq / "objects_in_camera/soup_can.txt");
  ASSERT_EQ(can.samples.size(), 3u);
  EXPECT_LT(TranslationDistanceM(can.samples[0].pose, d.frames[1].instances[2].record.T_camera_mesh()), 1e-9);
  EXPECT_EQ(s.annotations, 9);
}

TEST(TumWriter, OptionsAreChecked) {
  EXPECT_THROW(TumExportOptions{.threads = -1}.check(), InputError);
  EXPECT_NO_THROW(TumExportOptions{}.check());
}

/// The re-imported depth equals the exported one within half a TUM unit (1/10000 m), pixel by pixel.
void ExpectSameDepth(const cv::Mat& exported_m, const DepthImage& reimported_m) {
  ASSERT_EQ(reimported_m.width, exported_m.cols);
  ASSERT_EQ(reimported_m.height, exported_m.rows);
  int64_t valid = 0;
  for (int v = 0; v < exported_m.rows; ++v)
    for (int u = 0; u < exported_m.cols; ++u) {
      const double d = exported_m.at<float>(v, u);
      ASSERT_NEAR(reimported_m.at(u, v), d, 0.5 / kTumDepthPerMetre + 1e-6) << u << "," << v;
      valid += d > 0;
    }
  EXPECT_GT(valid, exported_m.rows * exported_m.cols / 4);  // the simulated room: ~48 % in range
}

TEST(TumWriter, ReimportedByTheTumImporterGivesTheSamePosesAndDepth) {
  const testing::SimulatedLabels in = testing::SimulateAndLabel("tum_roundtrip");
  Dataset dataset = LoadDataset({{in.session, in.labels, {}}});
  SelectFrames(dataset, ExportFilterOptions{}, ExportSplitOptions{.by = SplitBy::kNone});
  ASSERT_GE(dataset.frames.size(), 6u);
  const WriteSummary s = WriteTum(dataset, in.dir / "tum");
  const fs::path seq = in.dir / "tum/train/000001";
  ExpectTumFiles(seq);
  EXPECT_EQ(s.images, static_cast<int64_t>(dataset.frames.size()));
  import::ImportTum(seq, in.dir / "back");
  const SessionReader back = SessionReader::Open(in.dir / "back");
  ASSERT_EQ(back.frame_count("rgbd"), static_cast<int64_t>(dataset.frames.size()));
  const ExportScene& scene = dataset.scenes[0];
  for (size_t i = 0; i < dataset.frames.size(); ++i) {
    const ExportFrame& f = dataset.frames[i];
    const auto index = static_cast<int64_t>(i);
    ASSERT_EQ(back.frame("rgbd", index).record.stamp_ns, f.stamp_ns);
    ASSERT_TRUE(f.T_tracker_camera);
    const InterpolatedPose pose = back.CameraPoseAtFrame("rgbd", index);
    ASSERT_TRUE(pose.ok()) << i;
    EXPECT_LT(TranslationDistanceM(*pose.pose, *f.T_tracker_camera), 1e-6) << i;
    EXPECT_LT(RadFromDeg(RotationDistanceDeg(*pose.pose, *f.T_tracker_camera)), 1e-9) << i;
    EXPECT_EQ(ReadText(back.ColorPath("rgbd", index)), ReadText(f.color_path));
    ExpectSameDepth(ColorAlignedDepthM(scene, f), back.LoadDepth("rgbd", index));
  }
  // The bottle's trajectory: T_tracker_camera * T_camera_mesh of its label in each frame.
  const auto bottle = import::ReadTumGroundTruth(seq / "objects/oil_bottle.txt");
  size_t k = 0;
  for (const ExportFrame& f : dataset.frames)
    for (const ExportInstance& e : f.instances)
      if (e.record.name == "oil_bottle" && e.record.has_pose) {
        ASSERT_LT(k, bottle.samples.size());
        EXPECT_EQ(bottle.samples[k].stamp_ns, f.stamp_ns);
        EXPECT_LT(TranslationDistanceM(bottle.samples[k++].pose, *f.T_tracker_camera * e.record.T_camera_mesh()), 1e-6);
      }
  EXPECT_EQ(k, dataset.frames.size());
}

}  // namespace
}  // namespace mocap::exporters
