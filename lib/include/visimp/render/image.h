// RGB images from frames: flat-shaded pictures of a mesh with one colour per face (the
// visibility map of `visimp visibility --png`, later the image-error views), and PNG output.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "visimp/render/frame.h"

namespace visimp {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  ///< rows top to bottom, 3 bytes per pixel
};

using Rgb = std::array<std::uint8_t, 3>;

/// Colours every pixel of `frame` by its face's colour, shaded by |N·view| (flat, two-sided,
/// with an ambient floor so faces seen edge-on stay readable); background is white.
RgbImage shade_frame(const Frame& frame, const RenderScene& scene, const std::vector<Rgb>& face_colors);

/// A size×size flat-shaded picture of `mesh` with one colour per face, seen from
/// `direction` (default: a 3/4 view above the front right), with the raster backend.
RgbImage render_face_colors(const Mesh& mesh, const std::vector<Rgb>& face_colors, int size,
                            const Vec3& direction = Vec3{0.55, -0.7, 0.45});

/// Blue (0) → cyan → green → yellow → red (1): the error-map scale.
Rgb heat_color(double t);

/// Writes an 8-bit RGB PNG atomically; throws IoError.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace visimp
