// Depth-variation weights and the self-occluding-error test (see view_weights.h).
#include "visimp/cells/view_weights.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "visimp/core/bounding_box.h"

namespace visimp {
namespace {

std::vector<std::array<float, 3>> positions_relative_to(const Mesh& mesh, const Vec3& origin) {
  std::vector<std::array<float, 3>> out(mesh.num_vertices());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Vec3 p = mesh.positions[i] - origin;
    out[i] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  }
  return out;
}

}  // namespace

DepthImage capture_depth(const Mesh& mesh, const Vec3& eye, int resolution) {
  const BoundingBox box = bounding_box(mesh);
  const Vec3 c = box.center();
  const double radius = 0.5 * box.diagonal(), distance = norm(c - eye);
  // Half the field of view holds the bounding sphere; inside it, a wide view.
  const double half = distance > radius ? std::asin(radius / distance) * 1.05 : 85 * M_PI / 180;
  const double fov = std::min(170.0, std::max(1e-3, 2 * half * 180 / M_PI));
  DepthImage image;
  // The near plane as far out as the object allows: depth 1 − near/z is stored in float, so
  // a near plane far closer than the object would leave z with only a few digits.
  const double near = std::max(1e-4 * std::max(radius, 1e-30), 0.5 * (distance - radius));
  image.view = PerspectiveView::looking_at(eye, c, fov, resolution, near);
  PerspectiveView local = image.view;
  local.eye = Vec3{0, 0, 0};
  PerspectiveRasterizer raster;
  PerspectiveFrame frame;
  raster.draw(positions_relative_to(mesh, eye), mesh.faces, nullptr, local, frame);
  image.ids = std::move(frame.ids);
  image.distance.resize(frame.depth.size());
  for (std::size_t p = 0; p < frame.depth.size(); ++p) {
    image.distance[p] = image.ids[p] == 0 ? std::numeric_limits<float>::infinity()
                                          : static_cast<float>(image.view.near / (1.0 - frame.depth[p]));
  }
  return image;
}

std::vector<float> depth_variation_weights(const Mesh& mesh, const DepthImage& image) {
  const int size = image.view.resolution;
  const auto& z = image.distance;
  auto at = [&](int i, int j) { return z[static_cast<std::size_t>(j) * size + i]; };
  // Per pixel: the weight of what it shows.
  std::vector<float> pixel(z.size(), 0.0f);
  for (int j = 1; j + 1 < size; ++j) {
    for (int i = 1; i + 1 < size; ++i) {
      const float c = at(i, j);
      if (!std::isfinite(c)) continue;
      const float n[4] = {at(i - 1, j), at(i + 1, j), at(i, j - 1), at(i, j + 1)};
      float w = 0;
      bool border = false;
      float jump = 0;
      for (float v : n) {
        if (!std::isfinite(v))
          border = true;
        else
          jump = std::max(jump, std::abs(v - c) / c);
      }
      if (border) {
        w = 1;
      } else if (jump > 0.05f) {
        w = 0.75f;
      } else {
        // A crease: the second difference against the first (slope), both in each direction.
        const float dx2 = std::abs(n[0] + n[1] - 2 * c), dy2 = std::abs(n[2] + n[3] - 2 * c);
        const float dx1 = std::abs(n[1] - n[0]) * 0.5f, dy1 = std::abs(n[3] - n[2]) * 0.5f;
        // Against the slope, and at least one pixel's width at that distance: a facet edge of
        // a finely tessellated curve bends depth by a small fraction of a pixel and stays light.
        const float pixel_width = c * static_cast<float>(image.view.tan_half_fov) * 2 / static_cast<float>(size);
        const float scale = std::max({dx1, dy1, pixel_width});
        w = std::min(0.5f, 0.5f * std::max(dx2, dy2) / scale);
      }
      pixel[static_cast<std::size_t>(j) * size + i] = w;
    }
  }
  // Per vertex: the largest weight in the 3×3 pixels around its projection, if shown there.
  std::vector<float> out(mesh.num_vertices(), 0.0f);
  const PerspectiveView& v = image.view;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const Vec3 p = mesh.positions[k] - v.eye;
    const double depth = dot(p, v.forward);
    if (!(depth > v.near)) continue;
    const double x = (dot(p, v.right) / (depth * v.tan_half_fov) + 1) * 0.5 * size;
    const double y = (dot(p, v.up) / (depth * v.tan_half_fov) + 1) * 0.5 * size;
    const int pi = static_cast<int>(std::floor(x)), pj = static_cast<int>(std::floor(y));
    float best = 0;
    bool shown = false;
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        const int i = pi + di, j = pj + dj;
        if (i < 0 || j < 0 || i >= size || j >= size) continue;
        const float d = at(i, j);
        // The vertex is what this pixel shows when its depth matches (2% slack).
        if (std::isfinite(d) && std::abs(d - depth) <= 0.02 * depth) {
          shown = true;
          best = std::max(best, pixel[static_cast<std::size_t>(j) * size + i]);
        } else if (!std::isfinite(d)) {
          shown = true;  // next to the background: the vertex is on the outline
          best = 1;
        }
      }
    }
    out[k] = shown ? best : 0.0f;
  }
  return out;
}

double self_occluding_error(const Mesh& mesh, const Vec3& centre, const std::array<Vec3, 6>& corners, int resolution,
                            double fov_degrees) {
  // The SVMesh's faces: front-facing to the centre.
  std::vector<std::uint32_t> front;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 n = face_normal_unnormalized(mesh, mesh.faces[f]);
    if (dot(n, centre - mesh.positions[mesh.faces[f][0]]) > 0) front.push_back(static_cast<std::uint32_t>(f));
  }
  return self_occluding_error(mesh, front, corners, resolution, fov_degrees);
}

double self_occluding_error(const Mesh& mesh, const std::vector<std::uint32_t>& front,
                            const std::array<Vec3, 6>& corners, int resolution, double fov_degrees) {
  const BoundingBox box = bounding_box(mesh);
  PerspectiveRasterizer raster;
  PerspectiveFrame whole, partial;
  double worst = 0;
  const int size = resolution;
  std::vector<int> run_x(static_cast<std::size_t>(size) * size), run_y(run_x.size());
  for (const Vec3& corner : corners) {
    const auto relative = positions_relative_to(mesh, corner);
    PerspectiveView view = PerspectiveView::looking_at(corner, box.center(), fov_degrees, resolution,
                                                       1e-4 * std::max(box.diagonal(), 1e-30));
    view.eye = Vec3{0, 0, 0};
    raster.draw(relative, mesh.faces, nullptr, view, whole);
    raster.draw(relative, mesh.faces, &front, view, partial);
    auto hole = [&](int i, int j) {
      const std::size_t p = static_cast<std::size_t>(j) * size + i;
      return whole.ids[p] != 0 && partial.ids[p] == 0;
    };
    // Runs of hole pixels along rows and columns; a pixel's width is the shorter of its two.
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size;) {
        if (!hole(i, j)) {
          ++i;
          continue;
        }
        int e = i;
        while (e < size && hole(e, j)) ++e;
        for (int k = i; k < e; ++k) run_x[static_cast<std::size_t>(j) * size + k] = e - i;
        i = e;
      }
    }
    for (int i = 0; i < size; ++i) {
      for (int j = 0; j < size;) {
        if (!hole(i, j)) {
          ++j;
          continue;
        }
        int e = j;
        while (e < size && hole(i, e)) ++e;
        for (int k = j; k < e; ++k) run_y[static_cast<std::size_t>(k) * size + i] = e - j;
        j = e;
      }
    }
    for (int j = 0; j < size; ++j) {
      for (int i = 0; i < size; ++i) {
        if (hole(i, j)) {
          const std::size_t p = static_cast<std::size_t>(j) * size + i;
          worst = std::max(worst, static_cast<double>(std::min(run_x[p], run_y[p])));
        }
      }
    }
  }
  return worst;
}

}  // namespace visimp
