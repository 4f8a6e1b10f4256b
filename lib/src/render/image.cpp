// Flat shading from an ID frame and PNG output through libpng (see image.h).
#include "visimp/render/image.h"

#include <png.h>

#include <algorithm>
#include <cmath>

#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/render/renderer.h"

namespace visimp {

RgbImage shade_frame(const Frame& frame, const RenderScene& scene, const std::vector<Rgb>& face_colors) {
  const int size = frame.resolution();
  RgbImage image{size, size, std::vector<std::uint8_t>(static_cast<std::size_t>(size) * size * 3, 255)};
  std::vector<float> shade(scene.faces.size(), -1.0f);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const std::uint32_t id = frame.ids[static_cast<std::size_t>(y) * size + x];
      if (id == 0) continue;
      const std::size_t f = id - 1;
      if (shade[f] < 0) {
        const auto& a = scene.positions[scene.faces[f][0]];
        const auto& b = scene.positions[scene.faces[f][1]];
        const auto& c = scene.positions[scene.faces[f][2]];
        const Vec3 n = cross(Vec3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), Vec3(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
        const double length = norm(n);
        const double facing = length > 0 ? std::abs(dot(n, frame.view.direction)) / length : 0.0;
        shade[f] = static_cast<float>(0.35 + 0.65 * facing);
      }
      // Row 0 of a frame is the bottom; PNG rows run top to bottom.
      std::uint8_t* out = &image.rgb[(static_cast<std::size_t>(size - 1 - y) * size + x) * 3];
      for (int k = 0; k < 3; ++k) out[k] = static_cast<std::uint8_t>(std::lround(face_colors[f][k] * shade[f]));
    }
  }
  return image;
}

RgbImage render_face_colors(const Mesh& mesh, const std::vector<Rgb>& face_colors, int size, const Vec3& direction) {
  const RenderScene scene = RenderScene::from_mesh(mesh, false);
  const auto renderer = make_raster_renderer({size, 1});
  return shade_frame(render_view(*renderer, scene, direction), scene, face_colors);
}

Rgb heat_color(double t) {
  t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.0;
  const Rgb stops[5] = {{40, 60, 220}, {0, 200, 220}, {40, 190, 60}, {240, 220, 0}, {220, 30, 20}};
  const double x = t * 4;
  const int i = std::min(3, static_cast<int>(x));
  const double f = x - i;
  Rgb c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<std::uint8_t>(std::lround(stops[i][k] + (stops[i + 1][k] - stops[i][k]) * f));
  return c;
}

namespace {
void append_to_string(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), length);
}
void no_flush(png_structp) {}

// Encodes in memory; false when libpng reports an error (it longjmps here).
bool encode_png(const RgbImage& image, std::string& bytes) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, &bytes, append_to_string, no_flush);
  png_set_IHDR(png, info, static_cast<png_uint_32>(image.width), static_cast<png_uint_32>(image.height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < image.height; ++y) {
    png_write_row(png, &image.rgb[static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) * 3]);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}
}  // namespace

void write_png(const std::string& path, const RgbImage& image) {
  std::string bytes;
  if (!encode_png(image, bytes)) throw IoError(path, "libpng failed to encode the image");
  AtomicFileWriter file(path);
  file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.commit();
}

}  // namespace visimp
