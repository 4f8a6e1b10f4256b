#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "test_meshes.h"
#include "triangle_fill.h"
#include "visimp/core/portable_random.h"
#include "visimp/render/renderer.h"

namespace visimp {
namespace {

std::size_t count_id(const Frame& f, std::uint32_t id) {
  return static_cast<std::size_t>(std::count(f.ids.begin(), f.ids.end(), id));
}

// The camera on +z sees the grid (normals +z) face on.
Frame render_from_z(const Mesh& mesh, int resolution, bool cull = false) {
  const auto renderer = make_raster_renderer({resolution, 1});
  return render_view(*renderer, RenderScene::from_mesh(mesh, cull), Vec3{0, 0, 1});
}

std::size_t covered(const Frame& f) { return f.ids.size() - count_id(f, 0); }

// Pixels owned by face t of `mesh` drawn alone in the view of the whole mesh.
std::size_t covered_alone(const Mesh& mesh, std::size_t t, int resolution) {
  RenderScene scene = RenderScene::from_mesh(mesh, false);
  scene.faces = {mesh.faces[t]};
  const auto renderer = make_raster_renderer({resolution, 1});
  return covered(render_view(*renderer, scene, Vec3{0, 0, 1}));
}

TEST(Raster, SharedEdgesAreWatertight) {
  // A 7×7 grid seen face on at an awkward resolution: rendering every triangle alone and
  // adding up their pixels gives exactly the pixels of the whole grid - no pixel centre on
  // a shared edge is owned twice or missed.
  const Mesh g = test::grid(7);
  const Frame whole = render_from_z(g, 97);
  std::size_t sum = 0;
  for (std::size_t t = 0; t < g.faces.size(); ++t) sum += covered_alone(g, t, 97);
  EXPECT_EQ(sum, covered(whole));
  EXPECT_GT(covered(whole), 97u * 97u / 3);
}

TEST(Raster, PixelCentreOnASharedEdgeHasOneOwner) {
  // The square's diagonal maps to the image diagonal x = y, through 64 pixel centres
  // exactly: the top-left rule gives each of them to one of the two triangles.
  Mesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  const Frame both = render_from_z(m, 64);
  const std::size_t a = covered_alone(m, 0, 64), b = covered_alone(m, 1, 64);
  EXPECT_EQ(a + b, covered(both));
  EXPECT_EQ(count_id(both, 1) + count_id(both, 2), covered(both));
  // The diagonal's centres inside the square go to one side only: the counts differ by them.
  const std::size_t side =
      static_cast<std::size_t>(covered(both) > 0 ? std::lround(std::sqrt(double(covered(both)))) : 0);
  EXPECT_EQ(a > b ? a - b : b - a, side);
}

TEST(Raster, NearerFaceWinsAndBackFacesAreCulledOnlyWhenAsked) {
  Mesh m;
  // Face 0 at z = 0 facing +z, face 1 at z = 0.5 facing -z (a back face for the +z camera).
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {0, 1, 0}, {-1, -1, 0.5}, {0, 1, 0.5}, {1, -1, 0.5}};
  m.faces = {{0, 1, 2}, {3, 4, 5}};
  const Frame two_sided = render_from_z(m, 32, false);
  EXPECT_EQ(count_id(two_sided, 1), 0u);  // hidden behind the nearer back face
  EXPECT_GT(count_id(two_sided, 2), 0u);
  const Frame culled = render_from_z(m, 32, true);
  EXPECT_GT(count_id(culled, 1), 0u);
  EXPECT_EQ(count_id(culled, 2), 0u);
  // Depth is 0 near the camera, 1 far: the z = 0.5 face is nearer than the z = 0 one.
  const std::size_t centre = 16 * 32 + 16;
  EXPECT_LT(two_sided.depth[centre], culled.depth[centre]);
  EXPECT_EQ(two_sided.depth[0], 1.0f);
}

// A wide box's rows start near their first covered centre and stop after their run
// (triangle_fill.h): the centres drawn must be exactly those the full test of every centre
// draws. The full test is the narrow boxes' path, taken here strip by strip (each strip
// narrower than kSkipWidth). Long slivers at every angle, both windings, boxes cut by the
// image's edge.
TEST(Raster, WideTrianglesCoverExactlyTheCentresEveryCentreTestCovers) {
  constexpr int size = 256;
  SplitMix64 random(7);
  std::size_t drawn = 0;
  for (int t = 0; t < 3000; ++t) {
    ScreenVertex s[3];
    const double cx = -40 + 336 * random.uniform(), cy = -40 + 336 * random.uniform();
    const double angle = 6.283185307179586 * random.uniform(), length = 8 + 300 * random.uniform();
    const double width = t % 3 == 0 ? 0.05 + 2 * random.uniform() : 40 * random.uniform();  // slivers and fat ones
    const double ux = std::cos(angle), uy = std::sin(angle);
    const double px[3] = {cx - ux * length / 2, cx + ux * length / 2, cx + uy * width * (random.uniform() - 0.5) * 2};
    const double py[3] = {cy - uy * length / 2, cy + uy * length / 2, cy - ux * width * (random.uniform() - 0.5) * 2};
    for (int k = 0; k < 3; ++k)  // screen coordinates are positive (snap()); past 256 the box is clipped
      s[k] = {static_cast<float>(std::max(0.0, px[k])), static_cast<float>(std::max(0.0, py[k])), 0.5f};
    const raster::SnappedVertex p0 = raster::snap(s[0]), p1 = raster::snap(s[1]), p2 = raster::snap(s[2]);
    const int x0 = std::max(raster::first_centre(std::min({p0.x, p1.x, p2.x})), 0);
    const int x1 = std::min(raster::last_centre(std::max({p0.x, p1.x, p2.x})), size - 1);
    const int y0 = std::max(raster::first_centre(std::min({p0.y, p1.y, p2.y})), 0);
    const int y1 = std::min(raster::last_centre(std::max({p0.y, p1.y, p2.y})), size - 1);
    if (x0 > x1 || y0 > y1) continue;
    std::vector<std::uint32_t> whole(size * size, 0), strips(size * size, 0);
    std::vector<float> depth_whole(size * size, 1.0f), depth_strips(size * size, 1.0f);
    raster::fill_triangle(p0, p1, p2, &s[0], &s[1], &s[2], x0, x1, y0, y1, 1, false, size, whole.data(),
                          depth_whole.data());
    for (int x = x0; x <= x1; x += raster::kSkipWidth - 1)
      raster::fill_triangle(p0, p1, p2, &s[0], &s[1], &s[2], x, std::min(x + raster::kSkipWidth - 2, x1), y0, y1, 1,
                            false, size, strips.data(), depth_strips.data());
    ASSERT_EQ(whole, strips) << "triangle " << t;
    drawn += static_cast<std::size_t>(std::count(whole.begin(), whole.end(), 1u));
  }
  EXPECT_GT(drawn, 100000u);  // the triangles drew something
}

}  // namespace
}  // namespace visimp
