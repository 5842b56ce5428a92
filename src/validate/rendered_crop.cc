#include "validate/rendered_crop.h"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <future>
#include <mutex>
#include <thread>

#include "core/check.h"
#include "render/renderer.h"

namespace mocap {
namespace {

/// Largest virtual image side, pixels: a camera inside the model's bounding sphere would otherwise ask
/// for an unbounded image.
constexpr int kMaxImageSide = 2048;

struct RenderRequest {
  PinholeCamera camera;
  Rigid3d T_camera_mesh;
  std::promise<DepthImage> depth;
};

}  // namespace

TriangleMesh ToTriangleMesh(const Mesh& mesh) {
  TriangleMesh out;
  out.vertices.reserve(mesh.positions_m.size());
  for (const Eigen::Vector3f& p : mesh.positions_m) out.vertices.push_back(p.cast<double>());
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3)
    out.triangles.emplace_back(static_cast<int>(mesh.indices[i]), static_cast<int>(mesh.indices[i + 1]),
                               static_cast<int>(mesh.indices[i + 2]));
  return out;
}

/// Owns the GL context: renders queued requests one after another on its own thread.
class RenderedCropSource::RenderThread {
 public:
  RenderThread(const Mesh& mesh, const RenderContextOptions& context_options) {
    std::promise<void> ready;
    std::future<void> started = ready.get_future();
    thread_ = std::thread([this, &mesh, context_options, &ready] { Run(mesh, context_options, ready); });
    try {
      started.get();  // rethrows a context or upload failure here, in the constructor
    } catch (...) {
      thread_.join();
      throw;
    }
  }
  ~RenderThread() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }

  DepthImage Render(const PinholeCamera& camera, const Rigid3d& T_camera_mesh) {
    RenderRequest request{camera, T_camera_mesh, {}};
    std::future<DepthImage> depth = request.depth.get_future();
    {
      std::lock_guard lock(mutex_);
      queue_.push_back(std::move(request));
    }
    wake_.notify_one();
    return depth.get();
  }

 private:
  void Run(const Mesh& mesh, const RenderContextOptions& context_options, std::promise<void>& ready) {
    std::unique_ptr<RenderContext> context;
    std::unique_ptr<Renderer> renderer;
    MeshHandle handle;
    try {
      context = RenderContext::Create(context_options);
      RendererOptions options;
      options.outside_margin_fraction = 0.0;  // crops need the image only, not BOP's amodal canvas
      renderer = std::make_unique<Renderer>(*context, options);
      handle = renderer->Upload(mesh);
      ready.set_value();
    } catch (...) {
      ready.set_exception(std::current_exception());
      return;
    }
    RenderOutput out;
    for (;;) {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stop requested and nothing left
      RenderRequest request = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      try {
        const RenderItem item{handle, request.T_camera_mesh, 1};
        renderer->Render(request.camera, std::span<const RenderItem>(&item, 1), out);
        request.depth.set_value(out.depth_m);
      } catch (...) {
        request.depth.set_exception(std::current_exception());
      }
    }
  }

  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<RenderRequest> queue_;
  bool stop_ = false;
};

RenderedCropSource::RenderedCropSource(const Mesh& mesh, const CropOptions& options,
                                       const RenderContextOptions& context)
    : options_(options) {
  options_.check();
  context.check();
  if (mesh.positions_m.empty() || mesh.indices.size() < 3)
    throw InputError(Str("mesh ", mesh.source), "has no triangles");
  for (const Eigen::Vector3f& p : mesh.positions_m) vertices_.push_back(p.cast<double>());
  const Box3d box = BoundingBox(vertices_);
  center_model_ = 0.5 * (box.min + box.max);
  radius_m_ = 0.5 * (box.max - box.min).norm();
  thread_ = std::make_unique<RenderThread>(mesh, context);
}

RenderedCropSource::~RenderedCropSource() = default;

ModelCrop RenderedCropSource::Crop(const Rigid3d& T_camera_model) const {
  ModelCrop crop;
  crop.T_camera_model = T_camera_model;
  const Eigen::Vector3d eye_model = T_camera_model.inverse().translation();
  crop.view_direction_model = eye_model.normalized();
  const double distance_m = (eye_model - center_model_).norm();
  if (!(distance_m > 1e-6)) return crop;  // camera at the model centre: no defined view
  // Same camera centre, turned to look at the model centre (any image-up will do).
  const Rigid3d T_virtual_model = LookAt(eye_model, center_model_, Eigen::Vector3d::UnitZ());
  const double f = distance_m / options_.pixel_m;
  const double half_angle_tan = radius_m_ / std::max(distance_m - radius_m_, 0.05 * distance_m);
  const int half = std::min(kMaxImageSide / 2, static_cast<int>(std::ceil(f * half_angle_tan)) + 2);
  const PinholeCamera camera{2 * half + 1, 2 * half + 1, f, f, static_cast<double>(half), static_cast<double>(half), {}};
  const DepthImage depth_m = thread_->Render(camera, T_virtual_model);
  const Rigid3d T_model_virtual = T_virtual_model.inverse();
  for (int v = 0; v < depth_m.height; ++v)
    for (int u = 0; u < depth_m.width; ++u) {
      const float z = depth_m.at(u, v);
      if (z > 0) crop.points_model.push_back(T_model_virtual * camera.Unproject(Eigen::Vector2d(u, v), z));
    }
  return crop;
}

}  // namespace mocap
