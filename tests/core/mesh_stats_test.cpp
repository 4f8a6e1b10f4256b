#include "visimp/core/mesh_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <utility>

#include "test_meshes.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

TEST(MeshStats, GridHasItsOutlineAsBoundary) {
  // 3×3 grid: 16 vertices, 18 faces, 12 boundary edges (3 per side), one component.
  const MeshStats s = analyze(test::grid(3));
  EXPECT_EQ(s.vertices, 16u);
  EXPECT_EQ(s.faces, 18u);
  EXPECT_EQ(s.boundary_edges, 12u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_FALSE(s.closed_manifold());
  EXPECT_DOUBLE_EQ(s.area, 9.0);
}

TEST(MeshStats, CubeIsClosedManifold) {
  const MeshStats s = analyze(test::subdivided_cube(2));
  EXPECT_TRUE(s.closed_manifold());
  EXPECT_EQ(s.misoriented_edges, 0u);
  EXPECT_EQ(s.vertices, 26u);  // 8 corners + 12 edge midpoints + 6 face centres
  EXPECT_NEAR(s.area, 6.0, 1e-12);
}

TEST(MeshStats, FourFacesOnOneEdgeIsNonManifold) {
  //   four triangles share edge 0-1 (a "book" of 4 pages)
  Mesh m;
  m.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}};
  const MeshStats s = analyze(m);
  EXPECT_EQ(s.non_manifold_edges, 1u);
  EXPECT_EQ(s.boundary_edges, 8u);
}

TEST(MeshStats, BowTieVertexHasTwoFans) {
  //  2---1     two triangles touching only at vertex 0
  //   \ /.
  //    0
  //   / \.
  //  3---4
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}, {1, -1, 0}};
  m.faces = {{0, 1, 2}, {0, 3, 4}};
  const MeshStats s = analyze(m);
  EXPECT_EQ(s.non_manifold_vertices, 1u);
  EXPECT_EQ(s.components, 1u);
}

TEST(MeshStats, CountsMisorientedDuplicateDegenerateAndIsolated) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0, 0}, {5, 5, 5}};
  m.faces = {{0, 1, 2},
             {1, 2, 3},   // edge 1-2 traversed 1->2 by both: misoriented
             {0, 1, 2},   // duplicate of face 0 (edge 0-1 now has 2 faces)
             {0, 1, 4}};  // collinear: zero area
  const MeshStats s = analyze(m);
  EXPECT_EQ(s.duplicate_faces, 1u);
  EXPECT_EQ(s.degenerate_faces, 1u);
  EXPECT_EQ(s.isolated_vertices, 1u);
  EXPECT_GE(s.non_manifold_edges, 1u);  // edge 0-1 carries faces 0, 2 and 3
}

// Edges and duplicate faces are grouped by their lowest vertex before sorting; on random
// faces over a few vertices (hubs of many edges, vertices with none, repeated corners) the
// counts must be those of a plain map of every edge and face.
TEST(MeshStats, EdgeAndDuplicateCountsMatchAPlainCountOnRandomFaces) {
  std::mt19937 random_engine(5);
  auto random = [&random_engine] { return static_cast<std::uint32_t>(random_engine()); };
  for (int round = 0; round < 20; ++round) {
    Mesh m;
    const std::uint32_t vertices = 3 + random() % 40;
    for (std::uint32_t v = 0; v < vertices; ++v)
      m.positions.push_back({double(random() % 7), double(random() % 7), double(random() % 7)});
    const std::uint32_t faces = 1 + random() % 120;
    for (std::uint32_t f = 0; f < faces; ++f)
      m.faces.push_back({static_cast<VertexIndex>(random() % vertices), static_cast<VertexIndex>(random() % vertices),
                         static_cast<VertexIndex>(random() % vertices)});
    std::map<std::pair<VertexIndex, VertexIndex>, std::pair<int, int>> edges;  // faces, forward ones
    std::map<std::array<VertexIndex, 3>, int> corner_sets;
    for (const Face& f : m.faces) {
      for (int k = 0; k < 3; ++k) {
        const VertexIndex a = f[k], b = f[(k + 1) % 3];
        if (a == b) continue;
        auto& e = edges[{std::min(a, b), std::max(a, b)}];
        ++e.first;
        e.second += a < b;
      }
      std::array<VertexIndex, 3> t{f[0], f[1], f[2]};
      std::sort(t.begin(), t.end());
      ++corner_sets[t];
    }
    std::size_t boundary = 0, non_manifold = 0, misoriented = 0, duplicates = 0;
    for (const auto& [edge, e] : edges) {
      boundary += e.first == 1;
      non_manifold += e.first > 2;
      misoriented += e.first == 2 && e.second != 1;
    }
    for (const auto& [t, count] : corner_sets) duplicates += static_cast<std::size_t>(count - 1);
    const MeshStats s = analyze(m);
    EXPECT_EQ(s.edges, edges.size()) << round;
    EXPECT_EQ(s.boundary_edges, boundary) << round;
    EXPECT_EQ(s.non_manifold_edges, non_manifold) << round;
    EXPECT_EQ(s.misoriented_edges, misoriented) << round;
    EXPECT_EQ(s.duplicate_faces, duplicates) << round;
    EXPECT_EQ(surface_area(m), s.area) << round;  // metro --density's area: analyze()'s, to the bit
  }
}

TEST(MeshStats, MatchesTheSourcesTableForTheTeapot) {
  // meshes/SOURCES.md: 3 components, 160 boundary edges, 1 non-manifold vertex.
  const MeshStats s = analyze(read_mesh(test::bundled_mesh("teapot.ply")));
  EXPECT_EQ(s.faces, 6320u);
  EXPECT_EQ(s.components, 3u);
  EXPECT_EQ(s.boundary_edges, 160u);
  EXPECT_EQ(s.non_manifold_vertices, 1u);
}

TEST(MeshStats, MatchesTheSourcesTableForTheAneurysm) {
  // meshes/SOURCES.md: open, manifold, 1 component, 116 boundary edges.
  const MeshStats s = analyze(read_mesh(test::bundled_mesh("aneurysm_open.ply")));
  EXPECT_EQ(s.boundary_edges, 116u);
  EXPECT_EQ(s.non_manifold_edges, 0u);
  EXPECT_EQ(s.components, 1u);
}

}  // namespace
}  // namespace visimp
