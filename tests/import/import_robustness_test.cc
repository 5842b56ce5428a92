// Importers on hostile or damaged sources: names in other encodings, files cut short, a full disk,
// bytes meant for a terminal, out-of-range options. Each must end in a session that is whole or in an
// InputError naming the file, and never leave anything at --out.
#include "tests/pipeline/label_run_testing.h"
#include "tests/session/full_disk.h"

#include <opencv2/imgcodecs.hpp>

#include "session/import/bop_import.h"
#include "session/import/motive_csv.h"
#include "session/import/plus_mha.h"
#include "session/import/tracker_import.h"
#include "session/import/tum_import.h"
#include "session/reader.h"
#include "session/writer.h"
#include "test_util.h"

namespace mocap::import {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::InputErrorOf;
using testing::ReadAll;
using testing::RealData;
using testing::ScratchDir;

const char* const kMotiveTake = "optitrack_neon_calib/optitrack_take.csv";

std::string ReplaceAll(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = 0; (at = text.find(from, at)) != std::string::npos; at += to.size()) text.replace(at, from.size(), to);
  return text;
}

// The first `count` lines of `text`, as `head -n count` gives them.
std::string Head(const std::string& text, int count) {
  size_t end = 0;
  for (int i = 0; i < count && end != std::string::npos; ++i) end = text.find('\n', end + (i == 0 ? 0 : 1));
  return text.substr(0, end + 1);
}

void ExpectNothingAt(const fs::path& out) {
  EXPECT_FALSE(fs::exists(out)) << out;
  EXPECT_FALSE(fs::exists(PartialFolder(out))) << PartialFolder(out);
}

// --- 1. non-UTF-8 names, and imports published whole ---------------------------------------------

TEST(ImportNonUtf8, MotiveCp1252RigidBodyNameIsKeptAsUtf8) {
  ScratchDir scratch;
  const std::string csv = ReplaceAll(ReadAll(RealData(kMotiveTake)), "NEON_DISPLAY_CALIB", "K\xf6pfchen");
  const auto file = scratch.Write("take.csv", csv);
  const auto summary = ImportMotive(file, scratch.path() / "S");
  EXPECT_EQ(summary.bodies.count("motive/K\xc3\xb6pfchen"), 1u);
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  EXPECT_THAT(reader.manifest().trackers[0].bodies, ::testing::Contains("K\xc3\xb6pfchen"));
  EXPECT_EQ(reader.BodyRecords("motive", "K\xc3\xb6pfchen").size(), 241u);
}

TEST(ImportNonUtf8, TumCommentByteIsKeptAsUtf8) {
  ScratchDir scratch;
  const auto src = RealData("tum_fr1_desk_9frames");
  const std::string rgb = ReplaceAll(ReadAll(src / "rgb.txt"), "freiburg1_desk.bag", "freiburg1_desk\xe9.bag");
  scratch.Write("seq/rgb.txt", rgb);
  fs::copy_file(src / "depth.txt", scratch.path() / "seq/depth.txt");
  fs::copy_file(src / "groundtruth.txt", scratch.path() / "seq/groundtruth.txt");
  fs::create_directory_symlink(src / "rgb", scratch.path() / "seq/rgb");
  fs::create_directory_symlink(src / "depth", scratch.path() / "seq/depth");
  ImportTum(scratch.path() / "seq", scratch.path() / "S");
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  EXPECT_EQ(reader.manifest().cameras[0].serial, "rgbd_dataset_freiburg1_desk\xc3\xa9.bag");
  EXPECT_EQ(reader.manifest().cameras[0].model, "tum_fr1");
}

TEST(ImportNonUtf8, PlusFieldNameIsKeptAsUtf8) {
  ScratchDir scratch;
  const std::string mha = ReplaceAll(ReadAll(RealData("plus_ndi_tracking/TransformInterpolationTest.igs.mha")),
                                     "_Stylus =", "_Stylus\xb0 =");
  const auto summary = ImportPlus(scratch.Write("log.mha", mha), scratch.path() / "S");
  EXPECT_THAT(summary.notes, ::testing::Contains(HasSubstr("'Stylus\xc2\xb0'")));
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  EXPECT_EQ(reader.manifest().extra.at("plus").at("ignored_fields").at(0), "Stylus\xc2\xb0");
}

TEST(PublishWhole, AFailureWhileWritingLeavesNothingAndTheRerunSucceeds) {
  ScratchDir scratch;
  const fs::path out = scratch.path() / "S";
  fs::create_directory(out);  // an empty --out is allowed
  SessionManifest manifest;
  manifest.trackers.push_back({"t", "test", "", "tracker", {"b"}});
  EXPECT_THAT(InputErrorOf([&] {
                PublishSession(out, "source.csv", manifest, [&](SessionWriter&, const fs::path& dir) {
                  EXPECT_EQ(dir, PartialFolder(scratch.path() / "S"));
                  throw InputError("source.csv:7", "bad row");
                });
              }),
              HasSubstr("source.csv:7: bad row"));
  EXPECT_FALSE(fs::exists(PartialFolder(out)));
  EXPECT_TRUE(fs::is_empty(out));
  PublishSession(out, "source.csv", manifest, [](SessionWriter&, const fs::path&) {});
  EXPECT_TRUE(SessionReader::Open(out).manifest().complete);
  EXPECT_FALSE(fs::exists(PartialFolder(out)));
}

TEST(PublishWhole, LeftoverOfAKilledImportIsReplacedAnyOtherFolderRefused) {
  ScratchDir scratch;
  const fs::path out = scratch.path() / "S";
  scratch.Write("S.partial/manifest.json", "{\"complete\": false}");  // as a killed import leaves it
  ImportMotive(RealData(kMotiveTake), out);
  EXPECT_TRUE(SessionReader::Open(out).manifest().complete);
  scratch.Write("T.partial/notes.txt", "mine");
  EXPECT_THAT(InputErrorOf([&] { ImportMotive(RealData(kMotiveTake), scratch.path() / "T"); }),
              HasSubstr("T.partial: exists and is not a session left by an interrupted import"));
  EXPECT_EQ(ReadAll(scratch.path() / "T.partial/notes.txt"), "mine");
}

TEST(PublishWhole, ManifestErrorsNameTheSource) {
  ScratchDir scratch;
  SessionManifest manifest;
  manifest.trackers.push_back({"", "test", "", "tracker", {"b"}});  // no tracker name
  EXPECT_THAT(InputErrorOf([&] { PublishSession(scratch.path() / "S", "take.csv", manifest, [](auto&, auto&) {}); }),
              ::testing::StartsWith("take.csv: "));
  ExpectNothingAt(scratch.path() / "S");
}

// --- 2. Motive files shorter than their header says -------------------------------------------------

TEST(MotiveTruncated, HeadOf107LinesIsRefusedWithBothCounts) {
  ScratchDir scratch;
  const auto file = scratch.Write("take.csv", Head(ReadAll(RealData(kMotiveTake)), 107));
  EXPECT_THAT(InputErrorOf([&] { ReadMotiveCsv(file); }),
              HasSubstr("take.csv: the header declares 241 exported frames ('Total Exported Frames') but 100 frame rows follow"));
  EXPECT_THAT(InputErrorOf([&] { ImportMotive(file, scratch.path() / "S"); }), HasSubstr("241"));
  ExpectNothingAt(scratch.path() / "S");
}

TEST(MotiveTruncated, HeaderOnlyIsRefused) {
  ScratchDir scratch;
  const auto file = scratch.Write("take.csv", Head(ReadAll(RealData(kMotiveTake)), 7));
  EXPECT_THAT(InputErrorOf([&] { ImportMotive(file, scratch.path() / "S"); }),
              HasSubstr("declares 241 exported frames ('Total Exported Frames') but 0 frame rows follow"));
  ExpectNothingAt(scratch.path() / "S");
}

// --- 3. a full disk reports its real reason and leaves nothing ----------------------------------------

TEST(ImportFullDisk, ReasonIsNoSpaceLeftAndNothingIsLeftBehind) {
  ScratchDir scratch;
  const fs::path mount_point = scratch.path() / "disk";
  fs::create_directories(mount_point);
  const std::string result = mocap::testing::RunOnFullDiskInChild(mount_point, [&](const mocap::testing::SayFn& say) {
    const fs::path out = mount_point / "S";
    std::string error;
    try {
      ImportTum(RealData("tum_fr1_desk_9frames"), out);  // several MiB of images onto a 1 MiB disk
    } catch (const InputError& e) {
      error = e.what();
    }
    if (error.find("No space left on device") == std::string::npos) say("FAIL expected ENOSPC, got: " + error);
    if (error.find("Success") != std::string::npos) say("FAIL errno lost: " + error);
    if (fs::exists(out) || fs::exists(PartialFolder(out))) say("FAIL a session was left at " + out.string());
    say("OK " + error);
  });
  if (result.rfind("SKIP", 0) == 0) GTEST_SKIP() << result;
  EXPECT_EQ(result.substr(0, 3), "OK ") << result;
}

// --- 4. file bytes in messages are quoted and escaped --------------------------------------------------

TEST(MessageEscaping, MhaAndSceneGtBytesAreEscaped) {
  ScratchDir scratch;
  const std::string attack = "\x1b]0;owned\x07\x1b[2J";
  const auto mha = scratch.Write("x.mha", "ObjectType = Image\n" + attack + "\n");
  const std::string mha_error = InputErrorOf([&] { ImportPlus(mha, scratch.path() / "S"); });
  EXPECT_THAT(mha_error, HasSubstr("x.mha:2: expected 'Key = value', got '\\x1b]0;owned\\x07\\x1b[2J'"));
  EXPECT_THAT(mha_error, Not(HasSubstr("\x1b")));
  const auto status = scratch.Write(
      "y.mha", "ObjectType = Image\nDimSize = 0 0 1\nSeq_Frame0000_Timestamp = 1\nSeq_Frame0000_AToBTransform = 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
               "Seq_Frame0000_AToBTransformStatus = " + attack + "\nElementDataFile = LOCAL\n");
  EXPECT_THAT(InputErrorOf([&] { ImportPlus(status, scratch.path() / "S"); }), Not(HasSubstr("\x1b")));

  scratch.Write("models/models_info.json", R"({"1": {"diameter": 80.0}})");
  scratch.Write("models/obj_000001.ply", "ply\n");
  scratch.Write("scene/scene_camera.json", R"({"1": {"cam_K": [500, 0, 4, 0, 500, 3, 0, 0, 1]}})");
  scratch.Write("scene/scene_gt.json", "{\"1\": [" + attack + "]}");
  fs::create_directories(scratch.path() / "scene/rgb");
  cv::imwrite((scratch.path() / "scene/rgb/000001.png").string(), cv::Mat(6, 8, CV_8UC3, cv::Scalar(1, 2, 3)));
  const std::string json_error = InputErrorOf([&] { ImportBop(scratch.path() / "scene", scratch.path() / "models", scratch.path() / "S", BopOptions()); });
  EXPECT_THAT(json_error, HasSubstr("scene_gt.json: byte"));
  EXPECT_THAT(json_error, Not(HasSubstr("\x1b")));
  scratch.Write("scene/scene_gt.json", R"({"1\u001b[2J": []})");  // a JSON string may hold ESC escaped
  const std::string key_error = InputErrorOf([&] { ImportBop(scratch.path() / "scene", scratch.path() / "models", scratch.path() / "S", BopOptions()); });
  EXPECT_THAT(key_error, HasSubstr("scene_gt.json: key '1\\x1b[2J'"));
  ExpectNothingAt(scratch.path() / "S");
  // A TUM image name is shown in messages about the image: control bytes in it are refused, escaped.
  scratch.Write("seq/rgb.txt", "1.0 rgb/\x1b[2J.png\n");
  scratch.Write("seq/depth.txt", "");
  scratch.Write("seq/groundtruth.txt", "1.0 0 0 0 0 0 0 1\n");
  const std::string tum_error = InputErrorOf([&] { ImportTum(scratch.path() / "seq", scratch.path() / "S"); });
  EXPECT_THAT(tum_error, HasSubstr("rgb.txt:1: file name 'rgb/\\x1b[2J.png' contains control characters"));
  EXPECT_THAT(tum_error, Not(HasSubstr("\x1b")));
}

// --- 5. number options: TUM's depth factor, and ranges -------------------------------------------------

TEST(NumberOptions, TumDepthFactorSetsTheDepthUnit) {
  ScratchDir scratch;
  TumImportOptions options;
  options.depth_units_per_metre = 1000;  // a sensor storing millimetres
  const auto summary = ImportTum(RealData("tum_fr1_desk_9frames"), scratch.path() / "S", options);
  const SessionReader reader = SessionReader::Open(scratch.path() / "S");
  EXPECT_DOUBLE_EQ(reader.manifest().cameras[0].depth_unit_m, 1e-3);
  EXPECT_EQ(reader.manifest().extra.at("tum").at("depth_units_per_metre"), 1000.0);
  EXPECT_THAT(summary.notes, ::testing::Contains(HasSubstr("1000 units per metre")));
  EXPECT_DOUBLE_EQ(TumImportOptions{}.depth_units_per_metre, 5000.0);  // TUM's own factor by default
}

TEST(NumberOptions, OutOfRangeValuesAreRefusedNamingTheSetting) {
  EXPECT_THAT(InputErrorOf([] { CheckInRange(1e300, kBopFrameRateRangeHz, "--rate"); }),
              HasSubstr("--rate: must be between 0.01 and 100000 Hz, got 1e+300"));
  EXPECT_THAT(InputErrorOf([] { CheckInRange(std::nan(""), kTimeSpanRangeS, "--gap-limit"); }), HasSubstr("--gap-limit: "));
  EXPECT_EQ(CheckInRange(30, kBopFrameRateRangeHz, "--rate"), 30);
  ScratchDir scratch;
  BopImportOptions bop = BopOptions();
  bop.frame_rate_hz = 1e300;  // would put every stamp at 0 ns
  EXPECT_THAT(InputErrorOf([&] { ImportBop(RealData("bop_lmo_scene2/test/000002"), RealData("bop_lmo_scene2/models"), scratch.path() / "S", bop); }),
              HasSubstr("frame_rate_hz: must be between"));
  TumImportOptions tum;
  tum.depth_units_per_metre = 0;
  EXPECT_THAT(InputErrorOf([&] { ImportTum(RealData("tum_fr1_desk_9frames"), scratch.path() / "S", tum); }),
              HasSubstr("depth_units_per_metre: must be between 1 and"));
  ExpectNothingAt(scratch.path() / "S");
}

// --- 6. every BOP error names its file -----------------------------------------------------------------

TEST(BopDepthScale, NegativeOrZeroIsRefusedNamingTheFileAndImage) {
  ScratchDir scratch;
  scratch.Write("models/models_info.json", R"({"1": {"diameter": 80.0}})");
  scratch.Write("models/obj_000001.ply", "ply\n");
  scratch.Write("scene/scene_gt.json", R"({"1": [{"cam_R_m2c": [1,0,0,0,1,0,0,0,1], "cam_t_m2c": [0, 0, 900], "obj_id": 1}]})");
  fs::create_directories(scratch.path() / "scene/rgb");
  cv::imwrite((scratch.path() / "scene/rgb/000001.png").string(), cv::Mat(6, 8, CV_8UC3, cv::Scalar(1, 2, 3)));
  for (const char* scale : {"-1", "0"}) {
    scratch.Write("scene/scene_camera.json",
                  std::string(R"({"1": {"cam_K": [500, 0, 4, 0, 500, 3, 0, 0, 1], "depth_scale": )") + scale + "}}");
    EXPECT_THAT(InputErrorOf([&] { ImportBop(scratch.path() / "scene", scratch.path() / "models", scratch.path() / "S", BopOptions()); }),
                HasSubstr("scene_camera.json: \"1\" depth_scale: must be a positive number"));
  }
  scratch.Write("scene/scene_camera.json", R"({"1": {"cam_K": [-500, 0, 4, 0, 500, 3, 0, 0, 1]}})");
  EXPECT_THAT(InputErrorOf([&] { ImportBop(scratch.path() / "scene", scratch.path() / "models", scratch.path() / "S", BopOptions()); }),
              HasSubstr("scene_camera.json: \"1\" cam_K: focal lengths must be positive"));
  ExpectNothingAt(scratch.path() / "S");
}

}  // namespace
}  // namespace mocap::import
