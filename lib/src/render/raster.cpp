// visimp's CPU rasterizer for orthographic ID + depth frames (the triangle fill is shared with
// perspective.cpp, in triangle_fill.h). Only what visibility needs: no colour, no
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
#include "triangle_fill.h"

namespace visimp {
namespace {

using raster::first_centre;
using raster::last_centre;
using raster::snap;
using raster::SnappedVertex;

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

    raster::fill_triangle(p0, p1, p2, &v[face[0]], &v[face[1]], &v[face[2]], x0, x1, y0, y1,
                          static_cast<std::uint32_t>(f + 1), f < scene.culled_faces, size, ids, depth);
  }

  RenderOptions options_;
};

}  // namespace

std::unique_ptr<Renderer> make_raster_renderer(const RenderOptions& options) {
  return std::make_unique<RasterRenderer>(options);
}

}  // namespace visimp
