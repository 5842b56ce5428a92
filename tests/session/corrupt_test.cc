// Torn and corrupt records, truncated images and bad manifests: detected, never misread, and reported
// with the file and position.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <nlohmann/json.hpp>

#include "session/durable_file.h"
#include "session/image_io.h"
#include "session/reader.h"
#include "session/record_file.h"
#include "session/writer.h"
#include "session_test_util.h"

namespace mocap {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::TempDir;
using testing::TwoCameraManifest;

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteAll(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

/// A closed session with 10 events and one 64x48 kinect1 frame.
fs::path MakeSession(const TempDir& tmp) {
  const fs::path dir = tmp.path() / "S";
  auto writer = SessionWriter::Create(dir, TwoCameraManifest());
  for (int i = 0; i < 10; ++i) writer->WriteEvent({i * 100, "drop", "kinect1", "frame " + std::to_string(i)});
  writer->WriteCameraFrame("kinect1", {0, 0, 0, "", "", ""}, testing::TestColor(0, 64, 48), testing::TestDepth(0, 64, 48));
  writer->Close();
  return dir;
}

/// The offset just past the `n`th newline of `bytes`.
size_t EndOfLine(const std::string& bytes, int n) {
  size_t pos = 0;
  for (int i = 0; i < n; ++i) pos = bytes.find('\n', pos) + 1;
  return pos;
}

/// What a crash leaves: the manifest as written at Create (not complete, no record counts).
void MarkIncomplete(const fs::path& dir) {
  nlohmann::json manifest = nlohmann::json::parse(ReadAll(dir / "manifest.json"));
  manifest["complete"] = false;
  manifest.erase("stream_records");
  WriteAll(dir / "manifest.json", manifest.dump());
}

template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RecordFile, LineFramingRoundTrips) {
  const nlohmann::json record = {{"a", "tab\tand\nnewline"}, {"b", 1.0 / 3.0}};
  const std::string line = EncodeRecordLine(record);
  EXPECT_EQ(std::count(line.begin(), line.end(), '\n'), 1);
  EXPECT_EQ(std::count(line.begin(), line.end(), '\t'), 1);
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
  TempDir tmp;
  WriteAll(tmp.path() / "f.jsonl", line + line);
  const auto contents = ReadRecordFile(tmp.path() / "f.jsonl", false);
  ASSERT_EQ(contents.records.size(), 2u);
  EXPECT_EQ(contents.records[1].json, record);
  EXPECT_EQ(contents.records[1].line, 2);
}

TEST(RecordFile, TruncatedMidRecordDropsOnlyTheTornTail) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  MarkIncomplete(dir);
  const fs::path events = dir / "events.jsonl";
  const std::string bytes = ReadAll(events);
  const size_t ninth_end = EndOfLine(bytes, 9);
  for (size_t cut : {ninth_end + 1, ninth_end + 20, bytes.size() - 2, bytes.size() - 1}) {
    WriteAll(events, bytes.substr(0, cut));
    const SessionReader reader = SessionReader::Open(dir);
    ASSERT_EQ(reader.events().size(), 9u) << "cut at " << cut;
    EXPECT_EQ(reader.events()[8].detail, "frame 8");
    const auto& diagnostics = reader.diagnostics();
    const auto it = std::find_if(diagnostics.begin(), diagnostics.end(),
                                 [](const StreamDiagnostics& d) { return d.file == "events.jsonl"; });
    ASSERT_NE(it, diagnostics.end());
    EXPECT_TRUE(it->torn_tail);
  }
}

TEST(RecordFile, FlippedByteInTheMiddleIsAnErrorNamingTheLine) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  const fs::path events = dir / "events.jsonl";
  std::string bytes = ReadAll(events);
  const size_t third_line = bytes.find('\n', bytes.find('\n') + 1) + 1;
  const size_t digit = bytes.find("\"stamp_ns\":", third_line) + 11;  // "200" becomes "300": valid JSON
  ASSERT_EQ(bytes[digit], '2');
  bytes[digit] = '3';
  WriteAll(events, bytes);
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }),
              AllOf(HasSubstr("events.jsonl:3"), HasSubstr("checksum mismatch")));
  SessionReaderOptions lenient;
  lenient.skip_corrupt_records = true;
  const SessionReader reader = SessionReader::Open(dir, lenient);
  ASSERT_EQ(reader.events().size(), 9u);
  for (const auto& event : reader.events()) EXPECT_NE(event.detail, "frame 2");  // skipped, never misread
  EXPECT_EQ(reader.events()[2].stamp_ns, 300);
}

TEST(RecordFile, FlippedByteInTheLastRecordIsDropped) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  MarkIncomplete(dir);
  const fs::path events = dir / "events.jsonl";
  std::string bytes = ReadAll(events);
  bytes[bytes.size() - 20] ^= 0x01;
  WriteAll(events, bytes);
  EXPECT_EQ(SessionReader::Open(dir).events().size(), 9u);
}

TEST(RecordFile, AStreamCutAfterACleanCloseIsAnError) {
  // A session closed cleanly counts each stream's records in its manifest. A file cut afterwards (at a
  // line boundary, where no torn tail shows, or inside a line) loses records: an error naming the file,
  // not a warning while bodies silently lose their samples.
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  EXPECT_EQ(nlohmann::json::parse(ReadAll(dir / "manifest.json"))["stream_records"]["events.jsonl"], 10);
  const fs::path events = dir / "events.jsonl";
  const std::string bytes = ReadAll(events);
  const size_t fifth_end = EndOfLine(bytes, 5);
  WriteAll(events, bytes.substr(0, fifth_end));
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }),
              AllOf(HasSubstr("events.jsonl"), HasSubstr("holds 5 whole records"), HasSubstr("closed with 10")));
  WriteAll(events, bytes.substr(0, bytes.size() - 3));
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), AllOf(HasSubstr("events.jsonl"), HasSubstr("cut")));
  WriteAll(events, "");
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), HasSubstr("holds 0 whole records"));
  // Reading what is left stays possible on request.
  WriteAll(events, bytes.substr(0, fifth_end));
  SessionReaderOptions lenient;
  lenient.skip_corrupt_records = true;
  EXPECT_EQ(SessionReader::Open(dir, lenient).events().size(), 5u);
  WriteAll(events, bytes);
  EXPECT_EQ(SessionReader::Open(dir).events().size(), 10u);
}

TEST(BadInput, PngCutInHalfNamesTheFile) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  const SessionReader reader = SessionReader::Open(dir);
  for (const fs::path& path : {reader.ColorPath("kinect1", 0), reader.DepthPath("kinect1", 0)}) {
    const std::string bytes = ReadAll(path);
    WriteAll(path, bytes.substr(0, bytes.size() / 2));
  }
  EXPECT_THAT(ErrorOf([&] { reader.LoadColor("kinect1", 0); }),
              AllOf(HasSubstr("color/000000.png"), HasSubstr("truncated")));
  EXPECT_THAT(ErrorOf([&] { reader.LoadDepth("kinect1", 0); }),
              AllOf(HasSubstr("depth/000000.png"), HasSubstr("truncated")));
}

TEST(BadInput, GarbageAndMissingImagesNameTheFile) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  const SessionReader reader = SessionReader::Open(dir);
  WriteAll(reader.ColorPath("kinect1", 0), "not an image at all");
  EXPECT_THAT(ErrorOf([&] { reader.LoadColor("kinect1", 0); }), HasSubstr("color/000000.png: cannot decode"));
  fs::remove(reader.DepthPath("kinect1", 0));
  EXPECT_THAT(ErrorOf([&] { reader.LoadDepth("kinect1", 0); }), HasSubstr("depth/000000.png: image file is missing"));
  EXPECT_FALSE(SessionReader::Open(dir).frame("kinect1", 0).depth_present);
}

TEST(BadInput, EightBitDepthPngIsRefused) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  const SessionReader reader = SessionReader::Open(dir);
  fs::copy_file(reader.ColorPath("kinect1", 0), reader.DepthPath("kinect1", 0), fs::copy_options::overwrite_existing);
  EXPECT_THAT(ErrorOf([&] { reader.LoadDepth("kinect1", 0); }), HasSubstr("must be 16-bit single-channel"));
}

TEST(IdImage, ReadsEightAndSixteenBitIdsExactly) {
  TempDir tmp;
  cv::Mat ids16(3, 4, CV_16UC1), ids8(3, 4, CV_8UC1);
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 4; ++u) {
      ids16.at<uint16_t>(v, u) = static_cast<uint16_t>(v * 20000 + u * 1111);
      ids8.at<uint8_t>(v, u) = static_cast<uint8_t>(v * 100 + u);
    }
  ids16.at<uint16_t>(2, 3) = 65535;  // the largest id, exact through the decoder's float
  for (const cv::Mat& ids : {ids16, ids8}) {
    const fs::path path = tmp.path() / (ids.depth() == CV_16U ? "ids16.png" : "ids8.png");
    ASSERT_TRUE(cv::imwrite(path.string(), ids));
    const LabelImage read = ReadIdImage(path);
    ASSERT_EQ(read.width, 4);
    ASSERT_EQ(read.height, 3);
    for (int v = 0; v < 3; ++v)
      for (int u = 0; u < 4; ++u) {
        const int expected = ids.depth() == CV_16U ? ids.at<uint16_t>(v, u) : ids.at<uint8_t>(v, u);
        EXPECT_EQ(read.at(u, v), expected) << path << " (" << u << ", " << v << ")";
      }
  }
}

TEST(IdImage, BadFilesNameTheFile) {
  TempDir tmp;
  const fs::path missing = tmp.path() / "missing.png";
  EXPECT_THAT(ErrorOf([&] { ReadIdImage(missing); }), AllOf(HasSubstr("missing.png"), HasSubstr("missing")));
  const fs::path colour = tmp.path() / "colour.png";
  ASSERT_TRUE(cv::imwrite(colour.string(), cv::Mat(4, 4, CV_8UC3, cv::Scalar(1, 2, 3))));
  EXPECT_THAT(ErrorOf([&] { ReadIdImage(colour); }), AllOf(HasSubstr("colour.png"), HasSubstr("single-channel")));
  const fs::path cut = tmp.path() / "cut.png";
  ASSERT_TRUE(cv::imwrite(cut.string(), cv::Mat(64, 64, CV_16UC1, cv::Scalar(7))));
  const std::string bytes = ReadAll(cut);
  WriteAll(cut, bytes.substr(0, bytes.size() / 2));
  EXPECT_THAT(ErrorOf([&] { ReadIdImage(cut); }), AllOf(HasSubstr("cut.png"), HasSubstr("truncated")));
  WriteAll(cut, "not an image at all");
  EXPECT_THAT(ErrorOf([&] { ReadIdImage(cut); }), AllOf(HasSubstr("cut.png"), HasSubstr("not a PNG")));
}

TEST(BadInput, ManifestVersionAndFieldsAreChecked) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  const fs::path path = dir / "manifest.json";
  const nlohmann::json good = nlohmann::json::parse(ReadAll(path));

  nlohmann::json bad = good;
  bad["format_version"] = 99;
  WriteAll(path, bad.dump());
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }),
              AllOf(HasSubstr("manifest.json"), HasSubstr("format_version"), HasSubstr("99")));

  bad = good;
  bad["format_version"] = "1";
  WriteAll(path, bad.dump());
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), AllOf(HasSubstr("format_version"), HasSubstr("integer")));

  bad = good;
  bad["cameras"][1].erase("depth_unit_m");
  WriteAll(path, bad.dump());
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }),
              AllOf(HasSubstr("manifest.json: cameras[1]"), HasSubstr("missing field 'depth_unit_m'")));

  bad = good;
  bad["cameras"][0]["depth_unit_m"] = -1.0;
  WriteAll(path, bad.dump());
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), HasSubstr("depth_unit_m"));

  bad = good;
  bad["trackers"][0]["frame"] = "camera:nope";
  WriteAll(path, bad.dump());
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), HasSubstr("trackers[0].frame"));

  bad = good;
  bad["cameras"][0]["T_body_camera"]["q_wxyz"] = {2.0, 0.0, 0.0, 0.0};
  WriteAll(path, bad.dump());
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), AllOf(HasSubstr("T_body_camera"), HasSubstr("unit quaternion")));

  WriteAll(path, good.dump().substr(0, 100));
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }), AllOf(HasSubstr("manifest.json:byte"), HasSubstr("JSON")));

  WriteAll(path, good.dump());
  EXPECT_NO_THROW(SessionReader::Open(dir));
}

TEST(BadInput, RecordWithMissingFieldNamesFileAndLine) {
  TempDir tmp;
  const fs::path dir = MakeSession(tmp);
  WriteAll(dir / "events.jsonl", EncodeRecordLine({{"stamp_ns", 1}, {"kind", "x"}, {"stream", ""}, {"detail", ""}}) +
                                     EncodeRecordLine({{"stamp_ns", 2}, {"kind", "x"}, {"detail", ""}}));
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(dir); }),
              AllOf(HasSubstr("events.jsonl:2"), HasSubstr("missing field 'stream'")));
}

TEST(BadInput, MissingFolderOrManifest) {
  TempDir tmp;
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(tmp.path() / "nope"); }), HasSubstr("no such session folder"));
  EXPECT_THAT(ErrorOf([&] { SessionReader::Open(tmp.path()); }), HasSubstr("manifest.json"));
}

TEST(BadInput, FullDeviceRaisesErrorNamingTheFile) {
  // /dev/full answers every write with ENOSPC, as a full disk does.
  AppendFile full("/dev/full");
  EXPECT_THAT(ErrorOf([&] { full.Append("x\n"); }), AllOf(HasSubstr("/dev/full"), HasSubstr("No space left on device")));
}

}  // namespace
}  // namespace mocap
