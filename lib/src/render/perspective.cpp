// Perspective rasterization (see perspective.h): vertices to view space, triangles clipped
// against the near plane and a guard band three image half-widths wide (so snapped
// coordinates stay small enough for exact 64-bit edge functions), then filled like the
// orthographic frames.
#include "visimp/render/perspective.h"

#include <algorithm>
#include <cmath>

#include "triangle_fill.h"

namespace visimp {
namespace {

constexpr float kGuardBand = 3;  // |x| ≤ 3·tan(fov/2)·z: pixels within [−R, 2R]

raster::SnappedVertex snap_signed(const ScreenVertex& v) {
  return {static_cast<std::int32_t>(std::floor(v.x * static_cast<float>(raster::kSubpixel) + 0.5f)),
          static_cast<std::int32_t>(std::floor(v.y * static_cast<float>(raster::kSubpixel) + 0.5f))};
}

Vec3 normalized(const Vec3& v) {
  const double n = norm(v);
  return n > 0 ? v / n : Vec3{0, 0, 1};
}

}  // namespace

PerspectiveView PerspectiveView::looking_at(const Vec3& eye, const Vec3& target, double fov_degrees, int resolution,
                                            double near) {
  PerspectiveView view;
  view.eye = eye;
  view.forward = normalized(target - eye);
  const Vec3 world_up = std::abs(view.forward.z) > 0.99 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
  view.right = normalized(cross(view.forward, world_up));
  view.up = cross(view.right, view.forward);
  view.tan_half_fov = std::tan(fov_degrees * M_PI / 360.0);
  view.near = near;
  view.resolution = resolution;
  return view;
}

Vec3 PerspectiveView::pixel_ray(double i, double j) const {
  const double x = (2 * (i + 0.5) / resolution - 1) * tan_half_fov;
  const double y = (2 * (j + 0.5) / resolution - 1) * tan_half_fov;
  return forward + right * x + up * y;
}

void PerspectiveRasterizer::draw(const std::vector<std::array<float, 3>>& positions, const std::vector<Face>& faces,
                                 const std::vector<std::uint32_t>* subset, const PerspectiveView& view,
                                 PerspectiveFrame& out) {
  const std::size_t pixels = static_cast<std::size_t>(view.resolution) * static_cast<std::size_t>(view.resolution);
  out.ids.assign(pixels, 0);
  out.depth.assign(pixels, 1.0f);
  view_vertices_.resize(positions.size());
  // Only the vertices of the drawn faces are transformed: a culled frame pays for what it draws.
  if (stamp_.size() != positions.size() || ++frame_ == 0) {
    stamp_.assign(positions.size(), 0);
    frame_ = 1;
  }
  const float ex = static_cast<float>(view.eye.x), ey = static_cast<float>(view.eye.y),
              ez = static_cast<float>(view.eye.z);
  const std::array<float, 3> r{static_cast<float>(view.right.x), static_cast<float>(view.right.y),
                               static_cast<float>(view.right.z)};
  const std::array<float, 3> u{static_cast<float>(view.up.x), static_cast<float>(view.up.y),
                               static_cast<float>(view.up.z)};
  const std::array<float, 3> w{static_cast<float>(view.forward.x), static_cast<float>(view.forward.y),
                               static_cast<float>(view.forward.z)};
  auto transform = [&](VertexIndex i) {
    if (stamp_[i] == frame_) return;
    stamp_[i] = frame_;
    const float px = positions[i][0] - ex, py = positions[i][1] - ey, pz = positions[i][2] - ez;
    view_vertices_[i] = {px * r[0] + py * r[1] + pz * r[2], px * u[0] + py * u[1] + pz * u[2],
                         px * w[0] + py * w[1] + pz * w[2]};
  };
  const std::size_t count = subset ? subset->size() : faces.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t f = subset ? (*subset)[k] : static_cast<std::uint32_t>(k);
    for (VertexIndex i : faces[f]) transform(i);
    draw_face(f, faces, view, out);
  }
}

void PerspectiveRasterizer::draw_face(std::uint32_t f, const std::vector<Face>& faces, const PerspectiveView& view,
                                      PerspectiveFrame& out) {
  const int size = view.resolution;
  const float t = static_cast<float>(view.tan_half_fov), near = static_cast<float>(view.near);
  const float half = 0.5f * static_cast<float>(size);
  // Signed distances to the five clip planes (inside ≥ 0).
  auto plane = [&](const ViewVertex& v, int p) {
    switch (p) {
      case 0:
        return v.z - near;
      case 1:
        return kGuardBand * t * v.z - v.x;
      case 2:
        return kGuardBand * t * v.z + v.x;
      case 3:
        return kGuardBand * t * v.z - v.y;
      default:
        return kGuardBand * t * v.z + v.y;
    }
  };
  ViewVertex polygon[2][16];  // a triangle clipped by 5 planes has at most 8 vertices
  int n = 3;
  for (int k = 0; k < 3; ++k) polygon[0][k] = view_vertices_[faces[f][k]];
  int current = 0;
  for (int p = 0; p < 5; ++p) {
    const ViewVertex* in = polygon[current];
    bool all_in = true, all_out = true;
    for (int k = 0; k < n; ++k) {
      const bool inside = plane(in[k], p) >= 0;
      all_in &= inside;
      all_out &= !inside;
    }
    if (all_out) return;
    if (all_in) continue;
    // Sutherland–Hodgman against plane p.
    ViewVertex* clipped = polygon[1 - current];
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const ViewVertex& a = in[k];
      const ViewVertex& b = in[(k + 1) % n];
      const float da = plane(a, p), db = plane(b, p);
      if (m + 2 > 16) return;  // float error on a sliver: drop it rather than overrun
      if (da >= 0) clipped[m++] = a;
      if ((da >= 0) != (db >= 0)) {
        const float s = da / (da - db);
        clipped[m++] = {a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)};
      }
    }
    n = m;
    current = 1 - current;
    if (n < 3) return;
  }
  ScreenVertex screen[16];
  raster::SnappedVertex snapped[16];
  for (int k = 0; k < n; ++k) {
    const ViewVertex& v = polygon[current][k];
    const float inv = 1.0f / (v.z * t);
    screen[k] = {(v.x * inv + 1) * half, (v.y * inv + 1) * half, 1 - near / v.z};
    snapped[k] = snap_signed(screen[k]);
  }
  const std::uint32_t id = f + 1;
  for (int k = 1; k + 1 < n; ++k) {
    const raster::SnappedVertex p0 = snapped[0], p1 = snapped[k], p2 = snapped[k + 1];
    const int x0 = std::max(raster::first_centre(std::min({p0.x, p1.x, p2.x})), 0);
    const int x1 = std::min(raster::last_centre(std::max({p0.x, p1.x, p2.x})), size - 1);
    const int y0 = std::max(raster::first_centre(std::min({p0.y, p1.y, p2.y})), 0);
    const int y1 = std::min(raster::last_centre(std::max({p0.y, p1.y, p2.y})), size - 1);
    if (x0 > x1 || y0 > y1) continue;
    raster::fill_triangle(p0, p1, p2, &screen[0], &screen[k], &screen[k + 1], x0, x1, y0, y1, id, false, size,
                          out.ids.data(), out.depth.data());
  }
}

}  // namespace visimp
