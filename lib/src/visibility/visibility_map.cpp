// The paper's colour scale for V (white 0 → red → yellow → green 1) and pictures of it.
#include <algorithm>
#include <cmath>

#include "visimp/visibility/visibility.h"

namespace visimp {

Rgb visibility_color(double v) {
  v = std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0);
  auto mix = [](Rgb a, Rgb b, double t) {
    Rgb c;
    for (int k = 0; k < 3; ++k) c[k] = static_cast<std::uint8_t>(std::lround(a[k] + (b[k] - a[k]) * t));
    return c;
  };
  const Rgb white{255, 255, 255}, red{220, 0, 0}, yellow{240, 220, 0}, green{0, 170, 0};
  if (v < 1.0 / 3) return mix(white, red, 3 * v);
  if (v < 2.0 / 3) return mix(red, yellow, 3 * v - 1);
  return mix(yellow, green, 3 * v - 2);
}

RgbImage render_visibility_map(const Mesh& mesh, const std::vector<float>& face_visibility, int size) {
  std::vector<Rgb> colors(mesh.num_faces());
  for (std::size_t f = 0; f < colors.size(); ++f) colors[f] = visibility_color(face_visibility[f]);
  return render_face_colors(mesh, colors, size);
}

}  // namespace visimp
