// Frame backends behind one interface (DESIGN.md "render::Sampler"): a renderer walks a
// range of cameras, renders each into a Frame and hands it to a FrameConsumer on the worker
// thread that rendered it. Consumers keep one accumulator per worker, so backends never
// lock; results do not depend on which worker got which camera as long as consumers add
// integers (see visibility/tally.h).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/parallel.h"
#include "visimp/render/frame.h"

namespace visimp {

class FrameConsumer {
 public:
  virtual ~FrameConsumer() = default;
  /// Called once before rendering with the number of workers that will call consume().
  virtual void begin(unsigned workers) = 0;
  /// Called concurrently from different workers, each with its own `worker` < workers.
  virtual void consume(const Frame& frame, std::size_t camera, unsigned worker) = 0;
};

/// Hands every frame to several consumers in turn: one rendering pass, many uses (the
/// visibility tally and the patch bitfields read the same frames).
class FrameFanOut final : public FrameConsumer {
 public:
  explicit FrameFanOut(std::vector<FrameConsumer*> consumers) : consumers_(std::move(consumers)) {}
  void begin(unsigned workers) override {
    for (FrameConsumer* c : consumers_) c->begin(workers);
  }
  void consume(const Frame& frame, std::size_t camera, unsigned worker) override {
    for (FrameConsumer* c : consumers_) c->consume(frame, camera, worker);
  }

 private:
  std::vector<FrameConsumer*> consumers_;
};

/// Frame sizes every renderer and picture accepts, and the most worker threads it starts.
inline constexpr int kMinResolution = 16, kMaxResolution = 8192;
inline constexpr unsigned kMaxThreads = 1024;

struct RenderOptions {
  int resolution = 480;  ///< frame width and height in pixels, 16..8192
  unsigned threads = 0;  ///< worker threads; 0 = one per hardware thread
};

/// Receives the fraction of cameras done (0..1) from the coordinating thread.
class RenderObserver {
 public:
  virtual ~RenderObserver() = default;
  virtual void on_render_progress(double fraction) = 0;
};

class Renderer {
 public:
  virtual ~Renderer() = default;
  virtual std::string name() const = 0;
  /// Frame width and height in pixels.
  virtual int resolution() const = 0;
  /// Renders cameras [first, last) of `cameras`.
  virtual void render(const RenderScene& scene, const CameraSet& cameras, std::size_t first, std::size_t last,
                      FrameConsumer& consumer, RenderObserver* observer = nullptr) = 0;
};

/// visimp's own CPU rasterizer for ID + depth frames: exact integer edge functions on a
/// 1/256-pixel grid (watertight: a pixel centre on a shared edge belongs to one triangle).
std::unique_ptr<Renderer> make_raster_renderer(const RenderOptions& options);

/// Renders one view and returns its frame (pictures, tests).
Frame render_view(Renderer& renderer, const RenderScene& scene, const Vec3& direction);

/// Throws UsageError for a resolution or thread count out of range.
void check_render_options(const RenderOptions& options);

/// Runs `job(worker, camera)` for cameras [first, last) on `workers` threads taking cameras
/// in turn; reports progress from the calling thread. Shared by the backends.
void for_each_camera(std::size_t first, std::size_t last, unsigned workers, RenderObserver* observer,
                     const std::function<void(unsigned worker, std::size_t camera)>& job);

/// The loop every backend shares: for each camera of [first, last) on worker threads, set
/// up the worker's frame for the view, let `draw(worker, frame)` fill ids, depth and
/// vertices, and hand the frame to the consumer. `prepare(workers)` runs first, on the
/// calling thread, so a backend can size its per-worker state.
void render_frames(const RenderScene& scene, const CameraSet& cameras, std::size_t first, std::size_t last,
                   const RenderOptions& options, FrameConsumer& consumer, RenderObserver* observer,
                   const std::function<void(unsigned workers)>& prepare,
                   const std::function<void(unsigned worker, Frame& frame)>& draw);

}  // namespace visimp
