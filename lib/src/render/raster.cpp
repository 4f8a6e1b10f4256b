// visimp's CPU rasterizer for ID + depth frames. Only what visibility needs: no colour, no
// clipping (the view always contains the bounding sphere), no perspective.
//
// Vertices are snapped to a 1/256-pixel grid and coverage is decided with exact 64-bit
// integer edge functions and the top-left fill rule, so two triangles sharing an edge never
// both own, nor both miss, a pixel centre on it. Depth is interpolated in float from the
// triangle's plane; ties keep the triangle drawn first (GL_LESS), like the OSMesa backend.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "visimp/render/renderer.h"

namespace visimp {
namespace {

constexpr int kSubpixelBits = 8;
constexpr std::int32_t kSubpixel = 1 << kSubpixelBits;
constexpr std::int32_t kHalfPixel = kSubpixel / 2;

struct FixedPoint {
  std::int64_t x, y;
};

// Screen coordinates are positive (the view contains the bounding sphere with a margin),
// so adding 0.5 and truncating rounds to the nearest grid point.
struct SnappedVertex {
  std::int32_t x, y;
};
SnappedVertex snap(const ScreenVertex& v) {
  return {static_cast<std::int32_t>(v.x * static_cast<float>(kSubpixel) + 0.5f),
          static_cast<std::int32_t>(v.y * static_cast<float>(kSubpixel) + 0.5f)};
}

// Smallest pixel index i whose centre 256 i + 128 is >= lo, and largest with centre <= hi
// (an arithmetic shift is a floor division, also for negative values).
int first_centre(std::int32_t lo) { return (lo - kHalfPixel + kSubpixel - 1) >> kSubpixelBits; }
int last_centre(std::int32_t hi) { return (hi - kHalfPixel) >> kSubpixelBits; }

// For a counter-clockwise triangle in a y-up image, an edge a→b is a "left" edge when it
// runs downward and a "top" edge when it is horizontal and runs leftward. Pixel centres
// exactly on other edges are left to the neighbouring triangle: bias 1 turns >= into >.
std::int64_t fill_rule_bias(const FixedPoint& a, const FixedPoint& b) {
  const bool left = b.y < a.y;
  const bool top = b.y == a.y && b.x < a.x;
  return (left || top) ? 0 : 1;
}

class RasterRenderer final : public Renderer {
 public:
  explicit RasterRenderer(const RenderOptions& options) : options_(options) { check_render_options(options); }

  std::string name() const override { return "raster"; }
  int resolution() const override { return options_.resolution; }

  void render(const RenderScene& scene, const CameraSet& cameras, std::size_t first, std::size_t last,
              FrameConsumer& consumer, RenderObserver* observer) override {
    std::vector<std::vector<SnappedVertex>> snapped;
    std::vector<std::vector<std::uint32_t>> candidates;
    render_frames(
        scene, cameras, first, last, options_, consumer, observer,
        [&](unsigned workers) {
          snapped.resize(workers);
          candidates.resize(workers);
        },
        [&](unsigned worker, Frame& frame) { draw(scene, frame, snapped[worker], candidates[worker]); });
  }

 private:
  static void draw(const RenderScene& scene, Frame& frame, std::vector<SnappedVertex>& snapped,
                   std::vector<std::uint32_t>& candidates) {
    const int size = frame.resolution();
    const std::size_t pixels = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
    frame.ids.assign(pixels, 0);
    frame.depth.assign(pixels, 1.0f);
    project_vertices(scene, frame.view, frame.vertices);
    const std::vector<ScreenVertex>& v = frame.vertices;
    snapped.resize(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) snapped[i] = snap(v[i]);

    const std::array<float, 3> direction{static_cast<float>(frame.view.direction.x),
                                         static_cast<float>(frame.view.direction.y),
                                         static_cast<float>(frame.view.direction.z)};
    const bool use_clusters = scene.culled_faces > 0 && !scene.clusters.empty();
    const std::size_t face_count = scene.faces.size();
    // Pass 1, branch-free per face: keep the faces that may own a pixel centre (front-facing
    // when culling, and with a pixel centre inside their box). Most faces of a big mesh
    // cover none, and a data-dependent branch per face costs more than the test itself.
    candidates.resize(RenderScene::kClusterSize);
    for (std::size_t first = 0; first < face_count; first += RenderScene::kClusterSize) {
      if (use_clusters && scene.clusters[first / RenderScene::kClusterSize].all_back_facing(direction)) continue;
      const std::size_t last = std::min(face_count, first + RenderScene::kClusterSize);
      std::size_t kept = 0;
      for (std::size_t f = first; f < last; ++f) {
        const Face& face = scene.faces[f];
        const SnappedVertex p0 = snapped[face[0]], p1 = snapped[face[1]], p2 = snapped[face[2]];
        const bool facing = f >= scene.culled_faces ||
                            std::int64_t{p1.x - p0.x} * (p2.y - p0.y) > std::int64_t{p1.y - p0.y} * (p2.x - p0.x);
        const bool has_x = first_centre(std::min({p0.x, p1.x, p2.x})) <= last_centre(std::max({p0.x, p1.x, p2.x}));
        const bool has_y = first_centre(std::min({p0.y, p1.y, p2.y})) <= last_centre(std::max({p0.y, p1.y, p2.y}));
        candidates[kept] = static_cast<std::uint32_t>(f);
        kept += static_cast<std::size_t>(facing & has_x & has_y);
      }
      for (std::size_t k = 0; k < kept; ++k) draw_face(scene, candidates[k], snapped, frame);
    }
  }

  // Pass 2: one face that may own pixel centres.
  static void draw_face(const RenderScene& scene, std::uint32_t f, const std::vector<SnappedVertex>& snapped,
                        Frame& frame) {
    const std::vector<ScreenVertex>& v = frame.vertices;
    const int size = frame.resolution();
    std::uint32_t* ids = frame.ids.data();
    float* depth = frame.depth.data();
    const Face& face = scene.faces[f];
    const SnappedVertex p0 = snapped[face[0]], p1 = snapped[face[1]], p2 = snapped[face[2]];
    int x0 = std::max(first_centre(std::min({p0.x, p1.x, p2.x})), 0);
    int x1 = std::min(last_centre(std::max({p0.x, p1.x, p2.x})), size - 1);
    int y0 = std::max(first_centre(std::min({p0.y, p1.y, p2.y})), 0);
    int y1 = std::min(last_centre(std::max({p0.y, p1.y, p2.y})), size - 1);
    if (x0 > x1 || y0 > y1) return;

    FixedPoint a{p0.x, p0.y}, b{p1.x, p1.y}, c{p2.x, p2.y};
    const ScreenVertex* s0 = &v[face[0]];
    const ScreenVertex* s1 = &v[face[1]];
    const ScreenVertex* s2 = &v[face[2]];
    std::int64_t area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area2 == 0) return;
    if (area2 < 0) {
      if (f < scene.culled_faces) return;
      std::swap(b, c);
      std::swap(s1, s2);
      area2 = -area2;
    }

    // Edge function of edge p→q at pixel centre (x, y): (q - p) × (centre - p), >= 0 inside.
    const FixedPoint origin{x0 * kSubpixel + kHalfPixel, y0 * kSubpixel + kHalfPixel};
    auto edge_at_origin = [&](const FixedPoint& p, const FixedPoint& q) {
      return (q.x - p.x) * (origin.y - p.y) - (q.y - p.y) * (origin.x - p.x) - fill_rule_bias(p, q);
    };
    std::int64_t row0 = edge_at_origin(b, c), row1 = edge_at_origin(c, a), row2 = edge_at_origin(a, b);
    const std::int64_t step_x0 = -(c.y - b.y) * kSubpixel, step_y0 = (c.x - b.x) * kSubpixel;
    const std::int64_t step_x1 = -(a.y - c.y) * kSubpixel, step_y1 = (a.x - c.x) * kSubpixel;
    const std::int64_t step_x2 = -(b.y - a.y) * kSubpixel, step_y2 = (b.x - a.x) * kSubpixel;

    // Depth plane through the three (unsnapped) vertices, evaluated at pixel centres.
    const double inv_area = 1.0 / static_cast<double>(area2);
    const double ex1 = static_cast<double>(b.x - a.x), ey1 = static_cast<double>(b.y - a.y);
    const double ex2 = static_cast<double>(c.x - a.x), ey2 = static_cast<double>(c.y - a.y);
    const double dz1 = static_cast<double>(s1->depth) - s0->depth, dz2 = static_cast<double>(s2->depth) - s0->depth;
    const double dzdx = (dz1 * ey2 - dz2 * ey1) * inv_area * kSubpixel;
    const double dzdy = (dz2 * ex1 - dz1 * ex2) * inv_area * kSubpixel;
    const double z_origin =
        s0->depth +
        (dzdx * static_cast<double>(origin.x - a.x) + dzdy * static_cast<double>(origin.y - a.y)) / kSubpixel;
    const std::uint32_t id = static_cast<std::uint32_t>(f + 1);

    for (int y = y0; y <= y1; ++y) {
      std::int64_t w0 = row0, w1 = row1, w2 = row2;
      const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(size);
      for (int x = x0; x <= x1; ++x) {
        if ((w0 | w1 | w2) >= 0) {
          const float z = static_cast<float>(z_origin + dzdx * (x - x0) + dzdy * (y - y0));
          const std::size_t p = row + static_cast<std::size_t>(x);
          if (z < depth[p]) {
            depth[p] = z;
            ids[p] = id;
          }
        }
        w0 += step_x0;
        w1 += step_x1;
        w2 += step_x2;
      }
      row0 += step_y0;
      row1 += step_y1;
      row2 += step_y2;
    }
  }

  RenderOptions options_;
};

}  // namespace

std::unique_ptr<Renderer> make_raster_renderer(const RenderOptions& options) {
  return std::make_unique<RasterRenderer>(options);
}

}  // namespace visimp
