#include "session/writer.h"

#include <unistd.h>

#include <chrono>
#include <algorithm>
#include <cerrno>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <deque>
#include <fstream>
#include <iterator>
#include <functional>
#include <map>
#include <mutex>
#include <thread>

#include "core/check.h"
#include "core/text.h"
#include "core/utc_time.h"
#include "core/log.h"
#include "session/durable_file.h"
#include "session/image_io.h"
#include "session/record_file.h"

namespace mocap {
namespace fs = std::filesystem;

void SessionWriterOptions::check() const {
  const std::string where = "SessionWriterOptions";
  if (png_compression < -1 || png_compression > 9) throw InputError(where, "png_compression must be in -1..9");
  if (jpeg_quality < 1 || jpeg_quality > 100) throw InputError(where, "jpeg_quality must be in 1..100");
  if (encoder_threads < 1 || encoder_threads > 64) throw InputError(where, "encoder_threads must be in 1..64");
  if (max_pending_frames < 1) throw InputError(where, "max_pending_frames must be >= 1");
  if (sync_interval_ms < 1 || sync_interval_ms > 1000) throw InputError(where, "sync_interval_ms must be in 1..1000");
}

namespace {

/// One record in submission order. Image records become ready when their files are in place.
struct Job {
  AppendFile* file = nullptr;
  std::string line;  ///< the framed record, set when ready
  bool is_frame = false;
  bool ready = false;
  std::exception_ptr error;
  std::function<std::string()> work;  ///< produces `line` (runs on an encoder thread)
};

/// Moves a finished temporary file into place; the record is appended only after this.
void RenameIntoPlace(const fs::path& temp, const fs::path& path) {
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    throw InputError(path.string(), Str("rename failed: ", std::strerror(error)));
  }
}

std::string ImportExtension(const fs::path& source, bool depth) {
  const std::string ext = LowerExtension(source);
  const bool ok = depth ? (ext == ".png" || ext == ".exr") : (ext == ".png" || ext == ".jpg");
  if (!ok)
    throw InputError(source.string(), depth ? "depth images must be 16-bit .png or .exr" : "colour images must be .png or .jpg");
  return ext;
}

}  // namespace

struct SessionWriter::Impl {
  fs::path dir;
  SessionManifest manifest;
  SessionWriterOptions options;
  std::map<std::string, std::unique_ptr<AppendFile>> files;  ///< by stream name; "" is the event log
  std::map<std::string, int64_t> next_index;                 ///< per camera

  std::mutex mutex;  ///< guards everything below, and the manifest
  std::condition_variable work_cv, done_cv, sync_cv;
  std::deque<std::shared_ptr<Job>> order;  ///< submitted, not yet committed, in submission order
  std::deque<std::shared_ptr<Job>> work;   ///< waiting for an encoder thread
  int pending_frames = 0;
  int64_t records_written = 0;
  std::exception_ptr error;  ///< first failure; the writer refuses further writes after it
  bool error_raised = false;  ///< `error` has reached a caller, so the destructor need not log it again
  bool stopping = false;
  bool closed = false;
  std::mutex commit_mutex;  ///< serialises appends, so they follow submission order
  std::map<const AppendFile*, int64_t> records_appended;  ///< per stream file; guarded by commit_mutex
  std::vector<std::thread> threads;

  void EncoderLoop();
  void SyncLoop();
  void Commit();
  void Submit(std::shared_ptr<Job> job);
  void SyncAll();
  void ThrowIfFailed() {
    if (!error) return;
    error_raised = true;
    std::rethrow_exception(error);
  }
};

void SessionWriter::Impl::EncoderLoop() {
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mutex);
      work_cv.wait(lock, [&] { return stopping || !work.empty(); });
      if (work.empty()) return;
      job = std::move(work.front());
      work.pop_front();
    }
    try {
      job->line = job->work();
    } catch (...) {
      job->error = std::current_exception();
    }
    job->work = nullptr;  // releases the image copies now
    {
      std::lock_guard lock(mutex);
      job->ready = true;
    }
    Commit();
  }
}

void SessionWriter::Impl::Commit() {
  std::lock_guard commit_lock(commit_mutex);
  std::vector<std::shared_ptr<Job>> batch;
  {
    std::lock_guard lock(mutex);
    while (!order.empty() && order.front()->ready) {
      batch.push_back(std::move(order.front()));
      order.pop_front();
    }
    if (batch.empty()) return;
  }
  std::exception_ptr failure;
  int64_t appended = 0;
  {
    std::lock_guard lock(mutex);
    failure = error;
  }
  // Lines of consecutive records of one stream go out in one write.
  for (size_t i = 0; i < batch.size() && !failure; ++i) {
    if (batch[i]->error) {
      failure = batch[i]->error;
      break;
    }
    std::string bytes = std::move(batch[i]->line);
    size_t n = 1;
    for (; i + 1 < batch.size() && batch[i + 1]->file == batch[i]->file && !batch[i + 1]->error; ++i, ++n)
      bytes += batch[i + 1]->line;
    try {
      batch[i]->file->Append(bytes);
      appended += static_cast<int64_t>(n);
      records_appended[batch[i]->file] += static_cast<int64_t>(n);
    } catch (...) {
      failure = std::current_exception();
    }
  }
  std::lock_guard lock(mutex);
  for (const auto& job : batch) pending_frames -= job->is_frame ? 1 : 0;
  records_written += appended;
  if (failure && !error) error = failure;
  done_cv.notify_all();
}

void SessionWriter::Impl::Submit(std::shared_ptr<Job> job) {
  {
    std::unique_lock lock(mutex);
    ThrowIfFailed();
    MOCAP_CHECK(!closed, "write to a closed SessionWriter");
    if (job->is_frame) {
      done_cv.wait(lock, [&] { return pending_frames < options.max_pending_frames || error; });
      ThrowIfFailed();
      ++pending_frames;
    }
    order.push_back(job);
    if (job->work) {
      work.push_back(job);
      work_cv.notify_one();
      return;
    }
  }
  Commit();
}

void SessionWriter::Impl::SyncAll() {
  if (options.sync_images) {
    for (const auto& camera : manifest.cameras) {
      for (const char* kind : {"color", "depth"}) SyncDirectory(dir / "cameras" / camera.name / kind);
    }
  }
  for (auto& [name, file] : files) file->Sync();
}

void SessionWriter::Impl::SyncLoop() {
  std::unique_lock lock(mutex);
  while (!stopping) {
    sync_cv.wait_for(lock, std::chrono::milliseconds(options.sync_interval_ms));
    lock.unlock();
    try {
      SyncAll();
    } catch (...) {
      lock.lock();
      if (!error) error = std::current_exception();
      done_cv.notify_all();
      continue;
    }
    lock.lock();
  }
}

std::unique_ptr<SessionWriter> SessionWriter::Create(const fs::path& dir, const SessionManifest& manifest,
                                                     const SessionWriterOptions& options) {
  options.check();
  manifest.check();
  std::error_code error;
  if (fs::exists(dir, error) && !(fs::is_directory(dir) && fs::is_empty(dir)))
    throw InputError(dir.string(), "the session folder exists and is not empty; choose a new folder");
  auto impl = std::make_unique<Impl>();
  impl->dir = dir;
  impl->manifest = manifest;
  impl->manifest.complete = false;
  impl->manifest.format_version = kSessionFormatVersion;
  if (impl->manifest.created_utc.empty()) impl->manifest.created_utc = NowUtcIso8601();
  impl->options = options;
  fs::create_directories(dir, error);
  if (error) throw InputError(dir.string(), Str("cannot create the session folder: ", error.message()));
  for (const auto& camera : manifest.cameras) {
    const fs::path camera_dir = dir / "cameras" / camera.name;
    fs::create_directories(camera_dir / "color", error);
    fs::create_directories(camera_dir / "depth", error);
    if (error) throw InputError(camera_dir.string(), Str("cannot create folder: ", error.message()));
    impl->files[camera.name] = std::make_unique<AppendFile>(camera_dir / "frames.jsonl");
    impl->next_index[camera.name] = 0;
  }
  for (const auto& tracker : manifest.trackers) {
    const fs::path tracker_dir = dir / "trackers" / tracker.name;
    fs::create_directories(tracker_dir, error);
    if (error) throw InputError(tracker_dir.string(), Str("cannot create folder: ", error.message()));
    impl->files[tracker.name] = std::make_unique<AppendFile>(tracker_dir / "samples.jsonl");
  }
  impl->files[""] = std::make_unique<AppendFile>(dir / "events.jsonl");
  SaveManifest(dir, impl->manifest);
  Impl* raw = impl.get();
  for (int i = 0; i < options.encoder_threads; ++i) impl->threads.emplace_back([raw] { raw->EncoderLoop(); });
  impl->threads.emplace_back([raw] { raw->SyncLoop(); });
  return std::unique_ptr<SessionWriter>(new SessionWriter(std::move(impl)));
}

SessionWriter::SessionWriter(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

SessionWriter::~SessionWriter() {
  try {
    Close();
  } catch (const std::exception& e) {
    // An error the owner already caught (and reported) would otherwise be printed twice.
    if (!impl_->error_raised) Log().error("session {} left incomplete: {}", impl_->dir.string(), e.what());
  }
}

const fs::path& SessionWriter::dir() const { return impl_->dir; }

int64_t SessionWriter::records_written() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->records_written;
}

void SessionWriter::WriteCameraFrame(const std::string& camera, const CameraFrameRecord& record, const cv::Mat& color,
                                     const cv::Mat& depth) {
  if (!color.empty() && color.type() != CV_8UC3 && color.type() != CV_8UC1)
    throw InputError(camera, Str("frame ", record.frame, ": colour must be 8-bit BGR or grey"));
  const SessionWriterOptions& options = impl_->options;
  const std::string color_ext = options.color_encoding == ColorEncoding::kJpeg ? ".jpg" : ".png";
  ColorFileWriter write_color;
  if (!color.empty())
    write_color = [color = color.clone(), color_ext, options](const fs::path& temp) {
      const auto bytes = EncodeColor(color, color_ext, options.png_compression, options.jpeg_quality);
      WriteFileRemovingOnFailure(temp, {reinterpret_cast<const char*>(bytes.data()), bytes.size()}, options.sync_images);
    };
  SubmitCameraFrame(camera, record, color_ext, std::move(write_color), depth);
}

void SessionWriter::WriteCameraFrameJpeg(const std::string& camera, const CameraFrameRecord& record,
                                         std::shared_ptr<const std::vector<uint8_t>> color_jpeg, const cv::Mat& depth) {
  ColorFileWriter write_color;
  if (color_jpeg && !color_jpeg->empty()) {
    if (!IsWholeJpeg(*color_jpeg))
      throw InputError(camera, Str("frame ", record.frame, ": the colour is not a whole JPEG (no start-of-image or end-of-image marker, ",
                                   color_jpeg->size(), " bytes)"));
    write_color = [jpeg = std::move(color_jpeg), sync = impl_->options.sync_images](const fs::path& temp) {
      WriteFileRemovingOnFailure(temp, {reinterpret_cast<const char*>(jpeg->data()), jpeg->size()}, sync);
    };
  }
  SubmitCameraFrame(camera, record, ".jpg", std::move(write_color), depth);
}

void SessionWriter::SubmitCameraFrame(const std::string& camera, const CameraFrameRecord& record,
                                      const std::string& color_ext, ColorFileWriter write_color, const cv::Mat& depth) {
  const CameraStreamInfo* info = impl_->manifest.FindCamera(camera);
  if (!info) throw InputError(camera, "no such camera in the session manifest");
  if (!write_color && depth.empty()) throw InputError(camera, Str("frame ", record.frame, " has no image"));
  if (!depth.empty() && depth.type() != CV_16UC1 && depth.type() != CV_32FC1)
    throw InputError(camera, Str("frame ", record.frame, ": depth must be CV_16UC1 or CV_32FC1"));
  auto job = std::make_shared<Job>();
  job->file = impl_->files.at(camera).get();
  job->is_frame = true;
  int64_t index;
  {
    std::lock_guard lock(impl_->mutex);
    index = impl_->next_index[camera]++;
  }
  const fs::path camera_dir = impl_->dir / "cameras" / camera;
  const SessionWriterOptions options = impl_->options;
  const std::string depth_ext = options.depth_encoding == DepthEncoding::kExr ? ".exr" : ".png";
  CameraFrameRecord out = record;
  out.color_file = write_color ? "color/" + FrameFileStem(index) + color_ext : "";
  out.depth_file = depth.empty() ? "" : "depth/" + FrameFileStem(index) + depth_ext;
  job->work = [out, camera_dir, options, write_color = std::move(write_color), depth = depth.clone(),
               unit = info->depth_unit_m, depth_ext]() {
    if (write_color) {
      const fs::path path = camera_dir / out.color_file, temp = fs::path(path).concat(".tmp");
      write_color(temp);
      RenameIntoPlace(temp, path);
    }
    if (!depth.empty()) {
      const fs::path path = camera_dir / out.depth_file, temp = fs::path(path).concat(".tmp");
      if (depth_ext == ".exr") {
        WriteDepthExr(temp, depth, unit);
      } else {
        const auto bytes = EncodeDepthPng(depth, unit, options.png_compression);
        WriteFileRemovingOnFailure(temp, {reinterpret_cast<const char*>(bytes.data()), bytes.size()}, options.sync_images);
      }
      RenameIntoPlace(temp, path);
    }
    return EncodeRecordLine(ToJson(out));
  };
  impl_->Submit(std::move(job));
}

void SessionWriter::AddCameraFrameFiles(const std::string& camera, const CameraFrameRecord& record,
                                        const fs::path& color_source, const fs::path& depth_source) {
  if (!impl_->manifest.FindCamera(camera)) throw InputError(camera, "no such camera in the session manifest");
  if (color_source.empty() && depth_source.empty()) throw InputError(camera, Str("frame ", record.frame, " has no image"));
  auto job = std::make_shared<Job>();
  job->file = impl_->files.at(camera).get();
  job->is_frame = true;
  int64_t index;
  {
    std::lock_guard lock(impl_->mutex);
    index = impl_->next_index[camera]++;
  }
  CameraFrameRecord out = record;
  out.color_file = color_source.empty() ? "" : "color/" + FrameFileStem(index) + ImportExtension(color_source, false);
  out.depth_file = depth_source.empty() ? "" : "depth/" + FrameFileStem(index) + ImportExtension(depth_source, true);
  const fs::path camera_dir = impl_->dir / "cameras" / camera;
  job->work = [out, camera_dir, color_source, depth_source]() {
    // A listed source that does not exist stays listed but absent: readers count it as missing.
    if (!color_source.empty() && fs::exists(color_source)) LinkOrCopyFile(color_source, camera_dir / out.color_file);
    if (!depth_source.empty() && fs::exists(depth_source)) LinkOrCopyFile(depth_source, camera_dir / out.depth_file);
    return EncodeRecordLine(ToJson(out));
  };
  impl_->Submit(std::move(job));
}

void SessionWriter::WriteTrackerSample(const std::string& tracker, const TrackerRecord& record) {
  const TrackerStreamInfo* info = impl_->manifest.FindTracker(tracker);
  if (!info) throw InputError(tracker, "no such tracker in the session manifest");
  if (std::find(info->bodies.begin(), info->bodies.end(), record.body) == info->bodies.end())
    throw InputError(tracker, Str("body '", record.body, "' is not listed in the manifest's bodies of this tracker"));
  auto job = std::make_shared<Job>();
  job->file = impl_->files.at(tracker).get();
  job->line = EncodeRecordLine(ToJson(record));
  job->ready = true;
  impl_->Submit(std::move(job));
}

void SessionWriter::WriteEvent(const EventRecord& record) {
  auto job = std::make_shared<Job>();
  job->file = impl_->files.at("").get();
  job->line = EncodeRecordLine(ToJson(record));
  job->ready = true;
  impl_->Submit(std::move(job));
}

void SessionWriter::UpdateClockFit(const std::string& device, const ClockFit& fit) {
  std::lock_guard lock(impl_->mutex);
  impl_->ThrowIfFailed();
  MOCAP_CHECK(!impl_->closed, "UpdateClockFit on a closed SessionWriter");
  impl_->manifest.clock_fits[device] = fit;
  SaveManifest(impl_->dir, impl_->manifest);
}

void SessionWriter::Close() {
  {
    std::unique_lock lock(impl_->mutex);
    if (impl_->closed) return;
    impl_->closed = true;
    impl_->done_cv.wait(lock, [&] { return impl_->order.empty() || impl_->error; });
    impl_->stopping = true;
    impl_->work_cv.notify_all();
    impl_->sync_cv.notify_all();
  }
  for (auto& thread : impl_->threads) thread.join();
  impl_->threads.clear();
  impl_->ThrowIfFailed();
  impl_->SyncAll();
  {
    std::lock_guard commit_lock(impl_->commit_mutex);
    for (const auto& [name, file] : impl_->files)
      impl_->manifest.stream_records[fs::relative(file->path(), impl_->dir).generic_string()] =
          impl_->records_appended[file.get()];
  }
  impl_->manifest.complete = true;
  SaveManifest(impl_->dir, impl_->manifest);
}

}  // namespace mocap
