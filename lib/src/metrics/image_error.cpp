// Image RMS error (see image_error.h).
#include "visimp/metrics/image_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/render/image.h"
#include "box_filter.h"

namespace visimp {
namespace {

// Keeps one flat-shaded intensity image per camera at the output resolution: each pixel
// the mean of the supersample × supersample frame samples it covers.
class IntensityRecorder final : public FrameConsumer {
 public:
  IntensityRecorder(const Mesh& mesh, std::size_t cameras, int supersample)
      : images_(cameras), supersample_(static_cast<std::size_t>(supersample)) {
    normals_.reserve(mesh.num_faces());
    for (const Face& f : mesh.faces) {
      const Vec3 n = face_normal_unnormalized(mesh, f);
      const double length = norm(n);
      normals_.push_back(length > 0 ? n / length : Vec3{});
    }
  }
  void begin(unsigned) override {}
  void consume(const Frame& frame, std::size_t camera, unsigned) override {
    const auto samples = static_cast<std::size_t>(frame.resolution());
    const std::size_t size = samples / supersample_;
    const double scale = 255.0 / double(supersample_ * supersample_);
    std::vector<float>& image = images_[camera];
    image.assign(size * size, 0.0f);
    const Vec3 direction = frame.view.direction;
    detail::add_box_filtered(
        frame.ids.data(), samples, supersample_,
        [&](std::uint32_t id) { return scale * std::abs(dot(normals_[id - 1], direction)); }, image.data());
  }
  std::vector<std::vector<float>> take_images() { return std::move(images_); }

 private:
  std::vector<Vec3> normals_;
  std::vector<std::vector<float>> images_;
  std::size_t supersample_;
};

struct View {
  Vec3 center;
  double radius;
};

// The views frame A, the reference, alone when B fits in them, so that every B compared with
// the same A (QB and VG at every level) is measured against the very same images of A: a frame
// that followed B's box moved by a fraction of a pixel with each result and changed the
// aliasing of A's own images. A B reaching outside A's bounding sphere widens the frame to both.
View frame_views(const Mesh& a, const Mesh& b) {
  BoundingBox box = bounding_box(a);
  const BoundingBox box_b = bounding_box(b);
  if (box.empty()) return {box_b.center(), view_radius(box_b)};
  const View own{box.center(), view_radius(box)};
  if (box_b.empty()) return own;
  double farthest = 0;
  for (const Vec3& p : b.positions) farthest = std::max(farthest, squared_norm(p - own.center));
  if (std::sqrt(farthest) <= own.radius) return own;
  box.extend(box_b.min);
  box.extend(box_b.max);
  return {box.center(), view_radius(box)};
}

}  // namespace

namespace {

void check_options(const ImageErrorOptions& options) {
  if (options.supersample < 1 || options.supersample > 8)
    throw UsageError("image-error supersampling must be in 1..8, got " + std::to_string(options.supersample));
  const int samples = options.resolution * options.supersample;
  if (options.resolution < 16 || samples > 8192)
    throw UsageError("image-error resolution × supersampling must be in 16..8192, got " +
                     std::to_string(options.resolution) + " × " + std::to_string(options.supersample));
}

using ViewImages = std::vector<std::vector<float>>;

// The flat-shaded intensity images of `mesh` from the 20 views framed by `view`.
ViewImages render_views(const Mesh& mesh, const View& view, const ImageErrorOptions& options) {
  const auto renderer = make_raster_renderer({options.resolution * options.supersample, options.threads});
  const CameraSet cameras = dodecahedron_cameras();
  IntensityRecorder recorder(mesh, cameras.size(), options.supersample);
  renderer->render(RenderScene::from_mesh(mesh, false, view.center, view.radius), cameras, 0, cameras.size(), recorder);
  return recorder.take_images();
}

ImageError compare_views(const ViewImages& images_a, const ViewImages& images_b, const ImageErrorOptions& options) {
  ImageError out;
  out.resolution = options.resolution;
  out.supersample = options.supersample;
  out.views = images_a.size();
  const auto size = static_cast<std::size_t>(options.resolution);
  double total = 0;
  for (std::size_t n = 0; n < images_a.size(); ++n) {
    const std::vector<float>&ia = images_a[n], &ib = images_b[n];
    double d = 0;
    for (std::size_t p = 0; p < ia.size(); ++p) {
      const double diff = double(ia[p]) - double(ib[p]);
      d += diff * diff;
    }
    total += d;
    out.view_rms.push_back(std::sqrt(d / double(size * size)));
    if (!options.difference_prefix.empty()) {
      RgbImage diff{options.resolution, options.resolution, std::vector<std::uint8_t>(size * size * 3, 0)};
      for (std::size_t y = 0; y < size; ++y)
        for (std::size_t x = 0; x < size; ++x) {
          const std::size_t p = y * size + x, q = ((size - 1 - y) * size + x) * 3;  // PNG rows top-down
          diff.rgb[q] = static_cast<std::uint8_t>(std::lround(std::min(255.0f, std::abs(ia[p] - ib[p]))));
        }
      write_png(options.difference_prefix + std::to_string(n) + ".png", diff);
    }
  }
  out.rms = std::sqrt(total);
  out.rms_per_pixel = std::sqrt(total / (double(out.views) * double(size * size)));
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

ImageError image_error(const Mesh& a, const Mesh& b, const ImageErrorOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options);
  const View view = frame_views(a, b);
  ImageError out = compare_views(render_views(a, view, options), render_views(b, view, options), options);
  out.seconds = seconds_since(start);
  return out;
}

struct ImageErrorReference::Views {
  View view;
  ViewImages images;
};

ImageErrorReference::ImageErrorReference(const Mesh& a, const ImageErrorOptions& options) : a_(a), options_(options) {
  check_options(options);
  if (bounding_box(a).empty()) return;  // no frame of its own: each B frames the views (image_error())
  const View own = frame_views(a, a);
  own_ = std::make_unique<Views>(Views{own, render_views(a, own, options)});
}

ImageErrorReference::~ImageErrorReference() = default;

ImageError ImageErrorReference::error_to(const Mesh& b) const { return error_to(b, options_.difference_prefix); }

ImageError ImageErrorReference::error_to(const Mesh& b, const std::string& difference_prefix) const {
  const auto start = std::chrono::steady_clock::now();
  const View view = frame_views(a_, b);
  const bool own_frame = own_ && view.center == own_->view.center && view.radius == own_->view.radius;
  ViewImages widened;  // A in a frame widened for B
  if (!own_frame) widened = render_views(a_, view, options_);
  ImageErrorOptions options = options_;
  options.difference_prefix = difference_prefix;
  ImageError out = compare_views(own_frame ? own_->images : widened, render_views(b, view, options), options);
  out.seconds = seconds_since(start);
  return out;
}

}  // namespace visimp
