#pragma once
// Append-only, crash-safe writer of a session directory (docs/session-format.md).
//
// Crash safety: every image is encoded into a temporary name and renamed before its record is appended,
// so no record ever points at a half-written image. Records are appended with write(2) in the order the
// Write* calls were made (a camera record once its images are on disk) and fdatasync'd at least every
// `sync_interval_ms`. A writer killed with SIGKILL therefore leaves a session whose streams hold every
// record handed over more than about a second before the kill; a torn last line is detected by its
// checksum and ignored by the reader.
//
// Errors: a failed write (ENOSPC, EIO, ...) raises InputError naming the file; the writer then refuses
// further writes (the stream files are never appended to after a failure, so they stay well formed).
// Errors of background encoding are raised by the next Write*/Close call.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <string>
#include <vector>

#include "core/clock.h"
#include "session/manifest.h"
#include "session/records.h"

namespace mocap {

enum class ColorEncoding : uint8_t { kPng = 0, kJpeg = 1 };
enum class DepthEncoding : uint8_t { kPng16 = 0, kExr = 1 };

struct SessionWriterOptions {
  ColorEncoding color_encoding = ColorEncoding::kPng;
  DepthEncoding depth_encoding = DepthEncoding::kPng16;
  /// PNG compression level 0..9, or -1 for the speed-tuned defaults. Colour PNGs: zlib's level through
  /// OpenCV; -1 is OpenCV's speed path (level 1, SUB filter, RLE strategy), about a third of the time of
  /// an explicit level 1 at similar size. Depth PNGs: libdeflate's level (png_write.h); -1 is
  /// kDefaultDepthPngLevel, which encodes faster than OpenCV's speed path into ~11 % smaller files that
  /// read 1.7-2.3x faster (bench/RESULTS.md).
  int png_compression = -1;
  int jpeg_quality = 95;       ///< 1..100
  int encoder_threads = 2;     ///< image encoding threads, >= 1
  int max_pending_frames = 8;  ///< camera records in flight before WriteCameraFrame blocks, >= 1
  int sync_interval_ms = 200;  ///< fdatasync of the stream files at least this often, 1..1000
  /// fdatasync each image before it is renamed into place, so a record never outlives its image even
  /// across a power loss (a process crash needs no sync: the page cache survives it).
  bool sync_images = false;
  void check() const;
};

class SessionWriter {
 public:
  /// Creates `dir` (and parents) and writes manifest.json with complete = false. Throws InputError if
  /// `dir` exists and is not empty, or the manifest does not check().
  static std::unique_ptr<SessionWriter> Create(const std::filesystem::path& dir, const SessionManifest& manifest,
                                               const SessionWriterOptions& options = {});
  ~SessionWriter();
  SessionWriter(const SessionWriter&) = delete;
  SessionWriter& operator=(const SessionWriter&) = delete;

  /// Encodes and stores a colour image (CV_8UC3 BGR, or CV_8UC1) and/or a depth image (CV_16UC1 in the
  /// camera's depth_unit_m, or CV_32FC1 metres, 0 = invalid); either may be empty, not both. The images
  /// are copied, so the caller may reuse them at once. Blocks while max_pending_frames are in flight.
  /// The writer fills record.color_file / depth_file.
  void WriteCameraFrame(const std::string& camera, const CameraFrameRecord& record, const cv::Mat& color,
                        const cv::Mat& depth);
  /// The same for colour that arrives encoded as JPEG (a Kinect v2 sends its colour so): the bytes are
  /// stored as they are (color/NNNNNN.jpg), never decoded or re-encoded; `color_jpeg` is shared, not
  /// copied. It must be a whole JPEG (SOI at its start, EOI at its end), else InputError; either it or
  /// `depth` may be empty, not both. Readers decode it like any JPEG colour (ReadColor).
  void WriteCameraFrameJpeg(const std::string& camera, const CameraFrameRecord& record,
                            std::shared_ptr<const std::vector<uint8_t>> color_jpeg, const cv::Mat& depth);
  /// For importers: registers already-encoded image files (PNG/JPEG colour; 16-bit PNG or EXR depth)
  /// without decoding them. They are hard-linked into the session when possible, else copied. An empty
  /// path means no such image. A source path that does not exist is recorded as listed (the file name is
  /// kept) but absent: readers count it as missing, never as a frame.
  void AddCameraFrameFiles(const std::string& camera, const CameraFrameRecord& record,
                           const std::filesystem::path& color_source, const std::filesystem::path& depth_source);
  void WriteTrackerSample(const std::string& tracker, const TrackerRecord& record);
  void WriteEvent(const EventRecord& record);
  /// Stores (replaces) the clock fit of a device; rewrites manifest.json atomically.
  void UpdateClockFit(const std::string& device, const ClockFit& fit);
  /// Waits for pending images, syncs everything and marks the session complete. Idempotent. The
  /// destructor closes too (reporting a failure through the log, core/log.h, since it cannot throw).
  void Close();

  const std::filesystem::path& dir() const;
  /// Records appended so far (all streams).
  int64_t records_written() const;

 private:
  struct Impl;
  /// Writes the colour file of a frame to the given temporary path (null: the frame has no colour).
  using ColorFileWriter = std::function<void(const std::filesystem::path& temp)>;
  void SubmitCameraFrame(const std::string& camera, const CameraFrameRecord& record, const std::string& color_ext,
                         ColorFileWriter write_color, const cv::Mat& depth);
  explicit SessionWriter(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace mocap
