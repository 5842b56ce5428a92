// The COCO exporter: RLE strings, areas and boxes checked against values worked out by hand from cocoapi's
// maskApi.c format; an independent decoder (written here from the format description, sharing no code
// with the encoder) against many random masks and crops; the writer on an in-memory dataset and on a
// label run written by the labeller.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <sstream>

#include "exporters/coco/coco_rle.h"
#include "exporters/coco/coco_writer.h"
#include "exporters/dataset/selection.h"
#include "pipeline/label_stage.h"
#include "tests/pipeline/synthetic_inputs.h"

namespace mocap::exporters {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// ---- an independent reading of the format --------------------------------------------------------

/// The counts of a compressed RLE string: 5 bits per character (value - 48), least significant group
/// first, 0x20 = more groups follow, 0x10 of the last group = negative; from the 4th count on the value
/// is the difference to the count two before.
std::vector<int64_t> DecodeCounts(const std::string& text) {
  std::vector<int64_t> counts;
  size_t p = 0;
  while (p < text.size()) {
    int64_t value = 0;
    int bits = 0, c = 0;
    do {
      c = text.at(p++) - '0';
      value += static_cast<int64_t>(c & 31) * (int64_t{1} << bits);
      bits += 5;
    } while (c & 32);
    if (c & 16) value -= int64_t{1} << bits;  // two's complement of a `bits`-bit number
    if (counts.size() >= 3) value += counts[counts.size() - 2];
    counts.push_back(value);
  }
  return counts;
}

/// The h x w 0/1 mask of a compressed RLE (runs fill columns top to bottom, left to right).
cv::Mat DecodeMask(const std::string& text, int h, int w) {
  cv::Mat mask(h, w, CV_8UC1, cv::Scalar(0));
  int64_t position = 0;
  uint8_t value = 0;
  for (int64_t n : DecodeCounts(text)) {
    EXPECT_GE(n, 0);
    for (int64_t k = 0; k < n; ++k, ++position) {
      EXPECT_LT(position, int64_t{h} * w);
      if (position < int64_t{h} * w) mask.at<uint8_t>(static_cast<int>(position % h), static_cast<int>(position / h)) = value;
    }
    value = 1 - value;
  }
  EXPECT_EQ(position, int64_t{h} * w) << "counts do not cover the image";
  return mask;
}

/// COCO box [x, y, x_max - x_min + 1, y_max - y_min + 1] by scanning pixels; zeros when empty.
std::array<double, 4> BruteBox(const cv::Mat& mask) {
  int x_min = mask.cols, y_min = mask.rows, x_max = -1, y_max = -1;
  for (int v = 0; v < mask.rows; ++v)
    for (int u = 0; u < mask.cols; ++u)
      if (mask.at<uint8_t>(v, u)) x_min = std::min(x_min, u), x_max = std::max(x_max, u), y_min = std::min(y_min, v), y_max = std::max(y_max, v);
  if (x_max < 0) return {0, 0, 0, 0};
  return {double(x_min), double(y_min), double(x_max - x_min + 1), double(y_max - y_min + 1)};
}

cv::Mat MaskOf(std::initializer_list<std::initializer_list<int>> rows) {
  cv::Mat mask(static_cast<int>(rows.size()), static_cast<int>(rows.begin()->size()), CV_8UC1);
  int v = 0;
  for (const auto& row : rows) {
    int u = 0;
    for (int x : row) mask.at<uint8_t>(v, u++) = static_cast<uint8_t>(x);
    ++v;
  }
  return mask;
}

/// A 1 x n mask from run lengths, starting with 0s.
cv::Mat RowOfRuns(std::initializer_list<int> runs) {
  std::vector<uint8_t> pixels;
  uint8_t value = 0;
  for (int n : runs) pixels.insert(pixels.end(), n, value), value = 1 - value;
  return cv::Mat(pixels, true).reshape(1, 1);
}

// ---- (1) hand-computed -----------------------------------------------------------------------------

struct Expected {
  cv::Mat mask;
  std::vector<uint32_t> counts;
  std::string text;
  int64_t area;
  std::array<double, 4> box;
};

TEST(CocoRle, HandComputedMasks) {
  const std::vector<Expected> cases = {
      // Columns 000 | 110 | 011 | 000 -> 3 zeros, 2 ones, 2 zeros, 2 ones, 3 zeros; the 4th and 5th
      // counts are written as differences (2-2=0, 3-2=1).
      {MaskOf({{0, 1, 0, 0}, {0, 1, 1, 0}, {0, 0, 1, 0}}), {3, 2, 2, 2, 3}, "32201", 4, {1, 0, 2, 3}},
      {MaskOf({{1, 0}, {0, 0}}), {0, 1, 3}, "013", 1, {0, 0, 1, 1}},              // starts with a set pixel
      {cv::Mat(3, 4, CV_8UC1, cv::Scalar(0)), {12}, "<", 0, {0, 0, 0, 0}},       // empty: 48 + 12
      {cv::Mat(3, 4, CV_8UC1, cv::Scalar(255)), {0, 12}, "0<", 12, {0, 0, 4, 3}},  // full
      {cv::Mat(0, 0, CV_8UC1), {0}, "0", 0, {0, 0, 0, 0}},                         // no pixels at all
      // A run from the bottom of column 0 into column 1: one run, box spans both rows.
      {MaskOf({{0, 1}, {1, 1}}), {1, 3}, "13", 3, {0, 0, 2, 2}},
      // 40 = 0b01000 + 1*32 -> 'X' (8|0x20) then '1'; 60 = 28 + 32: 28 has bit 0x10, so a 0 group
      // must still follow ('l' then '1').
      {RowOfRuns({40, 60}), {40, 60}, "X1l1", 60, {40, 0, 60, 1}},
      {RowOfRuns({16}), {16}, "`0", 0, {0, 0, 0, 0}},  // 16 alone would read as -16: one more group
      // 4th count 5 - 10 = -5 -> 27 ('K'), a single group whose 0x10 bit marks it negative.
      {RowOfRuns({2, 10, 3, 5}), {2, 10, 3, 5}, "2:3K", 15, {2, 0, 18, 1}},
      // 50 = 18 + 32 -> 'b' '1'; 3rd count 1 written whole; 10 - 50 = -40 -> groups 24 (more) and 30.
      {RowOfRuns({0, 50, 1, 10}), {0, 50, 1, 10}, "0b11hN", 60, {0, 0, 61, 1}},
  };
  for (size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(Str("case ", i));
    const Expected& e = cases[i];
    const CocoRle rle = EncodeCocoRle(e.mask);
    EXPECT_EQ(rle.height, e.mask.rows);
    EXPECT_EQ(rle.width, e.mask.cols);
    EXPECT_EQ(rle.counts, e.counts);
    EXPECT_EQ(CocoRleString(rle.counts), e.text);
    EXPECT_EQ(CocoRleArea(rle), e.area);
    EXPECT_EQ(CocoRleBox(rle), e.box);
    EXPECT_EQ(CocoRleCountsFromString(e.text, "test"), e.counts);
  }
}

TEST(CocoRle, CropEncodesLikeTheFullImageWithoutBuildingIt) {
  // 2x2 crop at (1, 1) of a 3-row, 4-column image: set pixels (u, v) = (1, 1) and (2, 2), positions
  // u * 3 + v = 4 and 8 -> columns 000 | 010 | 001 | 000.
  const CocoRle rle = EncodeCocoRle({1, 0, 0, 1}, PixelRect{1, 1, 2, 2}, 4, 3);
  EXPECT_EQ(rle.counts, (std::vector<uint32_t>{4, 1, 3, 1, 3}));
  // Partly outside the image: only (0, 0) of the image remains of a 2x2 crop at (-1, -1).
  EXPECT_EQ(EncodeCocoRle({1, 1, 1, 1}, PixelRect{-1, -1, 2, 2}, 4, 3).counts, (std::vector<uint32_t>{0, 1, 11}));
  EXPECT_EQ(EncodeCocoRle({}, PixelRect{}, 4, 3).counts, (std::vector<uint32_t>{12}));
}

TEST(CocoRle, MalformedStringsAreInputErrors) {
  EXPECT_THROW(CocoRleCountsFromString("X", "s"), InputError);   // ends inside a count
  EXPECT_THROW(CocoRleCountsFromString("3p", "s"), InputError);  // 'p' is 64: outside the alphabet
  EXPECT_THROW(CocoRleCountsFromString("K", "s"), InputError);   // first count negative
}

// ---- (2) random masks through the independent decoder ----------------------------------------------

/// Random blobs (rectangles) or noise, so that both long runs and single pixels occur.
std::vector<uint8_t> RandomCrop(int w, int h, std::mt19937& rng) {
  std::vector<uint8_t> crop(static_cast<size_t>(w) * h, 0);
  const int mode = std::uniform_int_distribution<int>(0, 3)(rng);
  if (mode == 0) {
    std::bernoulli_distribution on(std::uniform_real_distribution<double>(0, 1)(rng));
    for (uint8_t& p : crop) p = on(rng) ? 1 : 0;
  } else {
    for (int k = 0; k < mode * 2; ++k) {
      const int x0 = std::uniform_int_distribution<int>(0, w - 1)(rng), y0 = std::uniform_int_distribution<int>(0, h - 1)(rng);
      const int x1 = std::uniform_int_distribution<int>(x0, w - 1)(rng), y1 = std::uniform_int_distribution<int>(y0, h - 1)(rng);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) crop[static_cast<size_t>(y) * w + x] = (mode == 3 && k % 2) ? 0 : 255;
    }
  }
  return crop;
}

TEST(CocoRle, RandomMasksDecodeBackThroughAnIndependentDecoder) {
  const std::vector<cv::Size> sizes = {{1, 1}, {1, 37}, {37, 1}, {5, 7}, {64, 48}, {320, 240}};
  int checked = 0;
  for (uint32_t seed = 1; seed <= 400; ++seed) {
    std::mt19937 rng(seed);
    const cv::Size image = sizes[seed % sizes.size()];
    // Crops anywhere from fully inside to hanging over any border (and now and then wholly outside).
    std::uniform_int_distribution<int> x(-3, image.width), y(-3, image.height);
    PixelRect rect{x(rng), y(rng), 0, 0};
    rect.width = std::uniform_int_distribution<int>(1, image.width + 6)(rng);
    rect.height = std::uniform_int_distribution<int>(1, image.height + 6)(rng);
    if (seed % 7 == 0) rect = {0, 0, image.width, image.height};  // the crop is the image
    const std::vector<uint8_t> crop = RandomCrop(rect.width, rect.height, rng);
    cv::Mat full(image, CV_8UC1, cv::Scalar(0));
    for (int v = 0; v < rect.height; ++v)
      for (int u = 0; u < rect.width; ++u)
        if (crop[static_cast<size_t>(v) * rect.width + u] && rect.x + u >= 0 && rect.y + v >= 0 &&
            rect.x + u < image.width && rect.y + v < image.height)
          full.at<uint8_t>(rect.y + v, rect.x + u) = 1;
    SCOPED_TRACE(Str("seed ", seed));
    const CocoRle rle = EncodeCocoRle(crop, rect, image.width, image.height);
    const std::string text = CocoRleString(rle.counts);
    const cv::Mat decoded = DecodeMask(text, image.height, image.width);
    ASSERT_EQ(cv::countNonZero(decoded != full), 0);
    EXPECT_EQ(EncodeCocoRle(full).counts, rle.counts);
    EXPECT_EQ(CocoRleArea(rle), cv::countNonZero(full));
    EXPECT_EQ(CocoRleBox(rle), BruteBox(full));
    EXPECT_EQ(CocoRleCountsFromString(text, "test"), rle.counts);
    ++checked;
  }
  EXPECT_EQ(checked, 400);
}

// ---- (3) the writer ------------------------------------------------------------------------------

std::string ReadBytes(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

json ReadJson(const fs::path& file) { return json::parse(ReadBytes(file)); }

/// Two objects (one with a 90-degree discrete symmetry about z through (10 mm, 0, 0), one continuous),
/// one camera, four frames without instances in train and val.
Dataset InMemoryDataset(const fs::path& dir) {
  Dataset d;
  pipeline::LibraryObject a, b;
  a.id = 7, a.name = "mug", a.object_class = "cup", a.mesh_path = dir / "mug.ply";
  a.symmetries.push_back({pipeline::ObjectSymmetry::Type::kDiscrete, Eigen::Vector3d::UnitZ(), {0.01, 0, 0}, 90});
  b.id = 2, b.name = "can", b.object_class = "can", b.mesh_path = dir / "can.obj";
  b.symmetries.push_back({pipeline::ObjectSymmetry::Type::kContinuous, Eigen::Vector3d::UnitZ(), {0, 0, 0.005}, 0});
  d.objects.objects = {a, b};
  ExportScene& scene = d.scenes.emplace_back();
  scene.scene_id = 1, scene.name = "S/cam", scene.camera = "cam", scene.session_dir = dir / "S";
  scene.color_camera = testing::TestCamera();
  std::ofstream(dir / "c.png", std::ios::binary) << "not really a png";
  for (int i = 0; i < 4; ++i) {
    ExportFrame& f = d.frames.emplace_back();
    f.index = i, f.frame = 100 + i, f.stamp_ns = 1000 * i, f.im_id = i, f.color_path = dir / "c.png";
    f.split = i < 3 ? "train" : "val";
  }
  return d;
}

TEST(CocoWriter, InMemoryDatasetIsDeterministicAndLinksImages) {
  const fs::path dir = testing::FreshDir("coco_memory");
  const Dataset d = InMemoryDataset(dir);
  const WriteSummary s = WriteCoco(d, dir / "one", CocoOptions{.threads = 2});
  WriteCoco(d, dir / "two", CocoOptions{.threads = 1});
  EXPECT_EQ(s.images, 4);
  EXPECT_EQ(s.files, 6);
  EXPECT_EQ(s.images_per_split.at("train"), 3);
  for (const char* split : {"train", "val"})
    EXPECT_EQ(ReadBytes(dir / "one/annotations" / Str("instances_", split, ".json")),
              ReadBytes(dir / "two/annotations" / Str("instances_", split, ".json")));
  EXPECT_FALSE(fs::exists(dir / "one/annotations/instances_test.json"));
  EXPECT_EQ(ReadBytes(dir / "one/images/val/000001_000003.png"), "not really a png");
  const json val = ReadJson(dir / "one/annotations/instances_val.json");
  ASSERT_EQ(val["images"].size(), 1u);
  EXPECT_EQ(val["images"][0]["id"], 4);  // ids count over all splits
  EXPECT_EQ(val["images"][0]["file_name"], "000001_000003.png");
  EXPECT_EQ(val["images"][0]["frame"], 103);
  EXPECT_EQ(val["cameras"][0]["K"], json({300.0, 0.0, 159.5, 0.0, 300.0, 119.5, 0.0, 0.0, 1.0}));
  const json& cats = val["categories"];
  ASSERT_EQ(cats.size(), 2u);
  EXPECT_EQ(cats[0]["id"], 2);  // sorted by id
  EXPECT_EQ(cats[1]["supercategory"], "cup");
  EXPECT_EQ(cats[1]["mesh"], "mug.ply");
  EXPECT_EQ(cats[0]["symmetries_continuous"][0]["offset"], json({0.0, 0.0, 5.0}));
  const json& discrete = cats[1]["symmetries_discrete"];
  ASSERT_EQ(discrete.size(), 3u);  // 90, 180 and 270 degrees
  // 180 degrees about z through x = 10 mm: R = diag(-1, -1, 1), t = o - R o = (20 mm, 0, 0).
  EXPECT_NEAR(discrete[1][0].get<double>(), -1, 1e-12);
  EXPECT_NEAR(discrete[1][3].get<double>(), 20, 1e-9);
  EXPECT_NEAR(discrete[1][7].get<double>(), 0, 1e-9);
}

TEST(CocoWriter, OptionsAreChecked) {
  EXPECT_THROW(CocoOptions{.ignore_below_visib_fract = 1.5}.check(), InputError);
  EXPECT_THROW(CocoOptions{.threads = -1}.check(), InputError);
  EXPECT_NO_THROW(CocoOptions{}.check());
}

/// A label run of the synthetic rig written by the labeller (EGL), BOP-style full-size masks included
/// so the exported RLEs can be compared with files the exporter never reads. COCO_TEST_FRAMES sets the
/// frame count (default 6) for timing the writer on more frames.
struct LabelledInputs {
  testing::Inputs in;
  fs::path labels;
};
LabelledInputs LabelSynthetic(const std::string& name) {
  const char* frames_env = std::getenv("COCO_TEST_FRAMES");
  LabelledInputs out{testing::MakeInputs(name, frames_env ? std::atoi(frames_env) : 6), {}};
  out.labels = out.in.dir / "labels";
  pipeline::LabelRunRequest request;
  request.session_dir = out.in.session, request.rig_file = out.in.rig, request.objects_file = out.in.objects;
  request.out_dir = out.labels;
  request.label.output.write_bop_masks = true;
  request.command = {"mocaplabel", "label"};
  pipeline::RunLabel(request);
  return out;
}

/// Every annotation against the label run: its RLE decodes to the full-size visible mask file, area and
/// box agree with the pixels and with labels.jsonl, pose fields copied.
void CheckAnnotations(const json& coco, const fs::path& labels) {
  std::map<int64_t, json> images;
  for (const json& image : coco["images"]) images[image["id"].get<int64_t>()] = image;
  std::map<std::tuple<std::string, int64_t, int64_t>, json> records;  // (camera, index, instance)
  for (const json& r : testing::ReadJsonLines(labels / "labels.jsonl")) records[{r["camera"], r["index"], r["instance"]}] = r;
  for (const json& a : coco["annotations"]) {
    for (const char* key : {"id", "image_id", "category_id", "segmentation", "area", "bbox", "iscrowd"})
      ASSERT_TRUE(a.contains(key)) << key;
    const json& image = images.at(a["image_id"].get<int64_t>());
    const json& r = records.at({image["camera"], image["index"], a["instance"]});
    const int h = image["height"], w = image["width"];
    ASSERT_EQ(a["segmentation"]["size"], json({h, w}));
    const cv::Mat decoded = DecodeMask(a["segmentation"]["counts"], h, w);
    char stem[32];
    std::snprintf(stem, sizeof(stem), "%06d_%06d.png", image["index"].get<int>(), a["instance"].get<int>());
    const std::string kind = r["visib_source"] == "measured_depth" ? "mask_visib_depth" : "mask_visib";
    const cv::Mat file = cv::imread((labels / image["camera"].get<std::string>() / kind / stem).string(), cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(file.empty()) << stem;
    const cv::Mat expected = file > 0, got = decoded > 0;
    EXPECT_EQ(cv::countNonZero(got != expected), 0) << stem;
    EXPECT_EQ(a["area"], cv::countNonZero(decoded));
    EXPECT_EQ(a["area"], r["px_count_visib"]);
    using Box = std::array<double, 4>;
    EXPECT_EQ(a["bbox"].get<Box>(), BruteBox(decoded));
    EXPECT_EQ(a["pose"]["rvec"], r["rvec"]);
    EXPECT_EQ(a["pose"]["direction"], "object_to_camera");
    EXPECT_EQ(a["category_id"], r["object"]);
    EXPECT_EQ(a["ignore"], r["visib_fract"].get<double>() < 0.1);
  }
}

/// Exports a session's label run (written with BOP masks) into `out` as one train split and checks it.
void ExportAndCheck(const fs::path& session, const fs::path& labels, const fs::path& out) {
  Dataset dataset = LoadDataset({{session, labels, {}}});
  ExportFilterOptions filters;
  filters.verdicts.push_back("reject");  // every label, so the check sees as many masks as possible
  SelectFrames(dataset, filters, ExportSplitOptions{.by = SplitBy::kNone});
  const auto start = std::chrono::steady_clock::now();
  const WriteSummary s = WriteCoco(dataset, out);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("COCO export: %lld frames, %lld annotations in %.3f s (%.0f frames/s)\n", static_cast<long long>(s.images),
              static_cast<long long>(s.annotations), seconds, static_cast<double>(s.images) / seconds);
  ASSERT_GT(s.annotations, 0);
  const json coco = ReadJson(out / "annotations/instances_train.json");
  for (const char* key : {"info", "licenses", "images", "annotations", "categories"}) ASSERT_TRUE(coco.contains(key));
  EXPECT_EQ(static_cast<int64_t>(coco["annotations"].size()), s.annotations);
  for (const json& image : coco["images"]) {
    EXPECT_TRUE(fs::exists(out / "images/train" / image["file_name"].get<std::string>()));
    for (const char* key : {"id", "width", "height", "file_name"}) ASSERT_TRUE(image.contains(key));
  }
  for (const json& category : coco["categories"])
    for (const char* key : {"id", "name", "supercategory"}) ASSERT_TRUE(category.contains(key));
  CheckAnnotations(coco, labels);
}

TEST(CocoWriter, LabelRunExportDecodesToTheLabelRunsVisibleMasks) {
  const LabelledInputs in = LabelSynthetic("coco_labelled");
  ExportAndCheck(in.in.session, in.labels, in.in.dir / "coco");
}

/// The same on a label run given by COCO_TEST_SESSION and COCO_TEST_LABELS (labelled with --bop-masks),
/// e.g. `mocaplabel demo`'s session with several objects occluding each other.
TEST(CocoWriter, GivenLabelRunExportDecodesToItsVisibleMasks) {
  const char* session = std::getenv("COCO_TEST_SESSION");
  const char* labels = std::getenv("COCO_TEST_LABELS");
  if (session == nullptr || labels == nullptr) GTEST_SKIP() << "COCO_TEST_SESSION and COCO_TEST_LABELS not set";
  ExportAndCheck(session, labels, testing::FreshDir("coco_given"));
}

}  // namespace
}  // namespace mocap::exporters
