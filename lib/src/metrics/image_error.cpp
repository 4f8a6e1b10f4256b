// Image RMS error (see image_error.h).
#include "visimp/metrics/image_error.h"

#include <chrono>
#include <cmath>
#include <cstdint>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/bounding_box.h"
#include "visimp/render/image.h"

namespace visimp {
namespace {

// Keeps one flat-shaded intensity image per camera.
class IntensityRecorder final : public FrameConsumer {
 public:
  IntensityRecorder(const Mesh& mesh, std::size_t cameras) : images_(cameras) {
    normals_.reserve(mesh.num_faces());
    for (const Face& f : mesh.faces) {
      const Vec3 n = face_normal_unnormalized(mesh, f);
      const double length = norm(n);
      normals_.push_back(length > 0 ? n / length : Vec3{});
    }
  }
  void begin(unsigned) override {}
  void consume(const Frame& frame, std::size_t camera, unsigned) override {
    std::vector<std::uint8_t>& image = images_[camera];
    image.assign(frame.ids.size(), 0);
    for (std::size_t p = 0; p < frame.ids.size(); ++p) {
      const std::uint32_t id = frame.ids[p];
      if (id == 0) continue;
      const double facing = std::abs(dot(normals_[id - 1], frame.view.direction));
      image[p] = static_cast<std::uint8_t>(std::lround(255.0 * facing));
    }
  }
  const std::vector<std::uint8_t>& image(std::size_t camera) const { return images_[camera]; }

 private:
  std::vector<Vec3> normals_;
  std::vector<std::vector<std::uint8_t>> images_;
};

}  // namespace

ImageError image_error(const Mesh& a, const Mesh& b, const ImageErrorOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const auto renderer = make_raster_renderer({options.resolution, options.threads});
  BoundingBox box = bounding_box(a);
  const BoundingBox box_b = bounding_box(b);
  if (!box_b.empty()) {
    box.extend(box_b.min);
    box.extend(box_b.max);
  }
  const Vec3 center = box.center();
  const double radius = view_radius(box);
  const CameraSet cameras = dodecahedron_cameras();
  IntensityRecorder image_a(a, cameras.size()), image_b(b, cameras.size());
  renderer->render(RenderScene::from_mesh(a, false, center, radius), cameras, 0, cameras.size(), image_a);
  renderer->render(RenderScene::from_mesh(b, false, center, radius), cameras, 0, cameras.size(), image_b);

  ImageError out;
  out.resolution = options.resolution;
  out.views = cameras.size();
  const auto size = static_cast<std::size_t>(options.resolution);
  double total = 0;
  for (std::size_t n = 0; n < cameras.size(); ++n) {
    const std::vector<std::uint8_t>&ia = image_a.image(n), &ib = image_b.image(n);
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
          diff.rgb[q] = static_cast<std::uint8_t>(std::abs(int(ia[p]) - int(ib[p])));
        }
      write_png(options.difference_prefix + std::to_string(n) + ".png", diff);
    }
  }
  out.rms = std::sqrt(total);
  out.rms_per_pixel = std::sqrt(total / (double(out.views) * double(size * size)));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace visimp
