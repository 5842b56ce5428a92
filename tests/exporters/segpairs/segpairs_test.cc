// The segmentation-pairs exporter: class numbering and palette by hand; the class image of a hand-drawn
// 6x4 frame (single owners, same-class overlap, the z-buffer deciding overlaps of different classes,
// undecidable overlaps and left-out instances ignored); and a simulated, labelled session exported with
// one instance left out, every pixel checked against the label run's masks and instance image, the list
// files and classes.txt read back.
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <set>
#include <sstream>

#include "core/check.h"
#include "exporters/dataset/selection.h"
#include "exporters/segpairs/segpairs_writer.h"
#include "pipeline/label_stage.h"
#include "pipeline/record_stage.h"
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

std::vector<std::string> DataLines(const fs::path& file) {
  std::vector<std::string> lines;
  std::istringstream in(ReadText(file));
  for (std::string line; std::getline(in, line);)
    if (line.empty() || line[0] != '#') lines.push_back(line);
  return lines;
}

TEST(SegClasses, NumberedByLowestObjectIdWithVocColours) {
  pipeline::ObjectLibrary library;
  for (auto [id, name, cls] : {std::tuple{5, "mug", "cup"}, {2, "crate", "box"}, {9, "beaker", "cup"}, {3, "tin", "can"}}) {
    pipeline::LibraryObject o;
    o.id = id, o.name = name, o.object_class = cls;
    library.objects.push_back(o);
  }
  const std::vector<SegClass> classes = SegClasses(library);
  ASSERT_EQ(classes.size(), 3u);
  EXPECT_EQ(classes[0].name, "box");
  EXPECT_EQ(classes[0].id, 1);
  EXPECT_EQ(classes[1].name, "can");
  EXPECT_EQ(classes[1].id, 2);
  EXPECT_EQ(classes[2].name, "cup");
  EXPECT_EQ(classes[2].id, 3);
  EXPECT_EQ(classes[2].object_ids, (std::vector<int>{5, 9}));
  // VOCdevkit's labelcolormap: 1 (128,0,0), 2 (0,128,0), 3 (128,128,0), 4 (0,0,128), 8 (64,0,0), 255 (224,224,192).
  using Rgb = std::array<uint8_t, 3>;
  EXPECT_EQ(classes[2].rgb, (Rgb{128, 128, 0}));
  EXPECT_EQ(SegClassColourRgb(0), (Rgb{0, 0, 0}));
  EXPECT_EQ(SegClassColourRgb(4), (Rgb{0, 0, 128}));
  EXPECT_EQ(SegClassColourRgb(8), (Rgb{64, 0, 0}));
  EXPECT_EQ(SegClassColourRgb(255), (Rgb{224, 224, 192}));
}

cv::Mat Rows(int type, std::initializer_list<std::initializer_list<int>> rows) {
  cv::Mat m(static_cast<int>(rows.size()), static_cast<int>(rows.begin()->size()), CV_32SC1);
  int v = 0;
  for (const auto& row : rows) {
    int u = 0;
    for (int x : row) m.at<int>(v, u++) = x;
    ++v;
  }
  cv::Mat out;
  m.convertTo(out, type);
  return out;
}

/// The hand-drawn frame. z-buffer: instances 1, 2, 3 kept, 9 left out by the filters. Visible masks:
/// 1 (class 1) and 2 (class 2) overlap at (3,0), where the z-buffer shows 2, and at (2,1), where it
/// shows 1; 3 (class 1) overlaps 1 at (1,2), (2,2): same class; 4 (class 3, not in the z-buffer)
/// overlaps 2 at (4,2), where the z-buffer shows nothing: undecidable. (1,3) is 9's in the z-buffer but
/// in 3's visible mask; (3,3) is 2's in the z-buffer but in no visible mask (a hand in front).
struct HandFrame {
  cv::Mat ids = Rows(CV_16UC1, {{0, 1, 1, 2, 2, 0}, {0, 1, 1, 2, 2, 0}, {3, 3, 1, 2, 0, 0}, {3, 9, 0, 2, 0, 9}});
  std::vector<uint8_t> m1 = {1, 1, 1, 1, 1, 0, 1, 1, 0}, m2 = {0, 1, 1, 1, 1, 1, 0, 1, 1}, m3 = {1, 1, 1, 1, 1, 0}, m4 = {1};
  std::vector<SegInstanceMask> kept = {{1, 1, {1, 0, 3, 3}, &m1}, {2, 2, {2, 0, 3, 3}, &m2}, {1, 3, {0, 2, 3, 2}, &m3}, {3, 4, {4, 2, 1, 1}, &m4}};
};

TEST(SegClassImage, HandDrawnFrame) {
  const HandFrame f;
  const cv::Mat got = SegClassImage(f.ids, f.kept, 255);
  ASSERT_EQ(got.type(), CV_8UC1);
  const cv::Mat expected = Rows(CV_8UC1, {{0, 1, 1, 2, 2, 0}, {0, 1, 1, 2, 2, 0}, {1, 1, 1, 2, 255, 0}, {1, 1, 0, 0, 0, 255}});
  EXPECT_EQ(cv::countNonZero(got != expected), 0) << got;
  // Left-out pixels as background when asked; the undecidable overlap stays ignored.
  const cv::Mat background = SegClassImage(f.ids, f.kept, 255, false);
  EXPECT_EQ(background.at<uint8_t>(3, 5), 0);
  EXPECT_EQ(background.at<uint8_t>(2, 4), 255);
  // More than 254 classes: 16-bit, ignore 65535.
  const cv::Mat wide = SegClassImage(f.ids, f.kept, 65535);
  ASSERT_EQ(wide.type(), CV_16UC1);
  EXPECT_EQ(wide.at<uint16_t>(3, 5), 65535);
  EXPECT_EQ(wide.at<uint16_t>(0, 3), 2);
}

TEST(SegPairsWriter, OptionsAreChecked) {
  EXPECT_THROW(SegPairsOptions{.threads = -1}.check(), InputError);
  EXPECT_NO_THROW(SegPairsOptions{}.check());
}

/// The rules of segpairs_writer.h pixel by pixel from the label run's files: classes of the kept
/// visible masks covering the pixel, the z-buffer's instance. Adds the pixels in an overlap of
/// different classes to `overlaps` (so the caller can see the rule was exercised).
void ExpectClassImage(const cv::Mat& got, const ExportScene& scene, const ExportFrame& frame,
                      const std::map<int, int>& class_of_object, int64_t& overlaps) {
  const cv::Mat ids = cv::imread(scene.labels.InstancePng(scene.camera, frame.index).string(), cv::IMREAD_UNCHANGED);
  const std::vector<ObjectMasks> masks = ReadFrameMasks(scene, frame);
  for (int v = 0; v < got.rows; ++v)
    for (int u = 0; u < got.cols; ++u) {
      std::set<int> classes;
      int front_class = -1;
      const int front = ids.at<uint16_t>(v, u);
      bool front_kept = false;
      for (size_t i = 0; i < masks.size(); ++i) {
        const pipeline::LabelRecord& r = frame.instances[i].record;
        front_kept |= r.instance == front;
        if (!masks[i].at(VisibleMask(masks[i], r), u, v)) continue;
        classes.insert(class_of_object.at(r.object));
        if (r.instance == front) front_class = class_of_object.at(r.object);
      }
      int expected = classes.size() == 1 ? *classes.begin() : 0;
      if (classes.size() > 1) expected = front_class > 0 ? front_class : 255, ++overlaps;
      if (classes.empty() && front != 0 && !front_kept) expected = 255;
      ASSERT_EQ(got.at<uint8_t>(v, u), expected) << u << "," << v;
    }
}

/// The left-out instance's z-buffer pixels of frame 0 are ignored wherever no kept visible mask claims
/// them: most of them (where the table's measured-depth mask claims a pixel of the funnel's, the depth
/// agreeing with the table there, the table wins).
void ExpectLeftOutIgnored(const cv::Mat& got, const ExportScene& scene, int left_out_instance) {
  const cv::Mat ids = cv::imread(scene.labels.InstancePng(scene.camera, 0).string(), cv::IMREAD_UNCHANGED);
  const cv::Mat left_out = ids == left_out_instance;
  EXPECT_GT(cv::countNonZero(left_out), 1000);
  EXPECT_GT(cv::countNonZero(left_out & (got == 255)), 0.75 * cv::countNonZero(left_out));
  std::printf("frame 0: %d pixels ignored, %d of them the left-out instance's\n", cv::countNonZero(got == 255),
              cv::countNonZero(left_out & (got == 255)));
}

TEST(SegPairsWriter, SimulatedSessionWithALeftOutInstance) {
  const testing::SimulatedLabels in = testing::SimulateAndLabel("segpairs_sim");
  Dataset dataset = LoadDataset({{in.session, in.labels, {}}});
  SelectFrames(dataset, ExportFilterOptions{}, ExportSplitOptions{.by = SplitBy::kNone});
  ASSERT_EQ(dataset.frames.size(), 8u);
  for (size_t i = 0; i < 8; ++i) dataset.frames[i].split = i < 6 ? "train" : i == 6 ? "val" : "test";
  // The funnel (instance 2) left out of frame 0, as a verdict or flag filter would.
  auto& instances = dataset.frames[0].instances;
  const auto funnel = std::find_if(instances.begin(), instances.end(), [](const ExportInstance& e) { return e.record.name == "funnel"; });
  ASSERT_NE(funnel, instances.end());
  const int funnel_instance = funnel->record.instance;
  instances.erase(funnel);
  const WriteSummary s = WriteSegPairs(dataset, in.dir / "out", SegPairsOptions{.threads = 2});
  EXPECT_EQ(s.images, 8);
  EXPECT_EQ(s.annotations, 8 * 4 - 1);
  // Hand-checked against the built-in library: oil_bottle 1 bottle, funnel 2, engine_block 3 engine, table 4.
  EXPECT_EQ(DataLines(in.dir / "out/classes.txt"),
            (std::vector<std::string>{"0 background 0 0 0", "1 bottle 128 0 0", "2 funnel 0 128 0", "3 engine 128 128 0",
                                      "4 table 0 0 128", "255 ignore 224 224 192"}));
  EXPECT_EQ(DataLines(in.dir / "out/train.txt").size(), 6u);
  EXPECT_EQ(DataLines(in.dir / "out/val.txt"), (std::vector<std::string>{"val/000001_000006.png valannot/000001_000006.png"}));
  EXPECT_EQ(DataLines(in.dir / "out/test.txt").size(), 1u);
  const std::map<int, int> class_of_object = {{1, 1}, {2, 2}, {3, 3}, {4, 4}};
  int64_t overlaps = 0;
  for (const std::string& line : DataLines(in.dir / "out/train.txt")) {
    const std::string image = line.substr(0, line.find(' ')), label = line.substr(line.find(' ') + 1);
    const int im_id = std::stoi(image.substr(13, 6));
    const ExportFrame& frame = dataset.frames[static_cast<size_t>(im_id)];
    EXPECT_EQ(ReadText(in.dir / "out" / image), ReadText(frame.color_path));
    const cv::Mat got = cv::imread((in.dir / "out" / label).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(got.type(), CV_8UC1);
    ExpectClassImage(got, dataset.scenes[0], frame, class_of_object, overlaps);
    if (im_id == 0) ExpectLeftOutIgnored(got, dataset.scenes[0], funnel_instance);
  }
  std::printf("pixels in overlaps of different classes: %lld\n", static_cast<long long>(overlaps));
}

}  // namespace
}  // namespace mocap::exporters
