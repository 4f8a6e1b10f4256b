// Morton orders of faces and vertices: sorted by code, ties in index order, every index once.
#include "visimp/core/spatial_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "visimp/core/bounding_box.h"
#include "test_meshes.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

TEST(SpatialOrder, VerticesFollowTheirMortonCodesWithTiesInIndexOrder) {
  Mesh m;
  // Two points share a code (the same position) and must keep their index order.
  m.positions = {{1, 1, 1}, {0, 0, 0}, {0.5, 0.5, 0.5}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<std::uint32_t> order = spatial_vertex_order(m);
  // Codes: the origin 0 (twice), then the centre (top bits 000, then all ones), (0, 1, 0)
  // (top bits 010), (1, 0, 0) (100) and the far corner (all ones).
  EXPECT_EQ(order, (std::vector<std::uint32_t>{1, 3, 2, 5, 4, 0}));
}

TEST(SpatialOrder, FaceAndVertexOrdersAreSortedPermutationsOnARealMesh) {
  const Mesh m = read_mesh(test::bundled_mesh("bunny.ply"));
  const BoundingBox box = bounding_box(m);
  const Vec3 extent = box.max - box.min;
  const double scale = 1.0 / std::max({extent.x, extent.y, extent.z});
  const std::vector<std::uint32_t> vertices = spatial_vertex_order(m);
  ASSERT_EQ(vertices.size(), m.num_vertices());
  std::vector<std::uint32_t> seen(vertices);
  std::sort(seen.begin(), seen.end());
  std::vector<std::uint32_t> all(m.num_vertices());
  std::iota(all.begin(), all.end(), 0u);
  EXPECT_EQ(seen, all);
  for (std::size_t i = 1; i < vertices.size(); ++i) {
    const std::uint32_t a = morton_code((m.positions[vertices[i - 1]] - box.min) * scale);
    const std::uint32_t b = morton_code((m.positions[vertices[i]] - box.min) * scale);
    ASSERT_TRUE(a < b || (a == b && vertices[i - 1] < vertices[i])) << "at " << i;
  }
  const std::vector<std::uint32_t> faces = spatial_face_order(m);
  ASSERT_EQ(faces.size(), m.num_faces());
  std::vector<std::uint32_t> face_seen(faces);
  std::sort(face_seen.begin(), face_seen.end());
  for (std::size_t i = 0; i < face_seen.size(); ++i) ASSERT_EQ(face_seen[i], i);
}

// Vertices too: 600k points (three of the sort's parts of 2^18) with many shared codes.
TEST(SpatialOrder, VertexOrderIsTheSameForAnyThreadCount) {
  Mesh m;
  std::uint32_t state = 12345;
  auto next = [&] {  // a small LCG: the same points on every platform
    state = state * 1664525u + 1013904223u;
    return double(state >> 8) / double(1u << 24);
  };
  for (int i = 0; i < 600000; ++i) m.positions.push_back({next(), next() * 0.01, std::floor(next() * 64) / 64});
  const std::vector<std::uint32_t> one = spatial_vertex_order(m, 1);
  EXPECT_EQ(one, spatial_vertex_order(m, 2));
  EXPECT_EQ(one, spatial_vertex_order(m, 3));
  std::vector<std::uint32_t> seen(one);
  std::sort(seen.begin(), seen.end());
  for (std::size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], i);
}

// The radix sort split among threads (each part scattering behind the earlier parts) keeps
// the one-thread order: on a mesh of several parts' worth of faces, and a sorted one.
TEST(SpatialOrder, FaceOrderIsTheSameForAnyThreadCount) {
  const Mesh m = test::icosphere(7);  // 327,680 faces
  const std::vector<std::uint32_t> one = spatial_face_order(m, 1), three = spatial_face_order(m, 3);
  EXPECT_EQ(one, three);
  const BoundingBox box = bounding_box(m);
  const Vec3 extent = box.max - box.min;
  const double scale = 1.0 / std::max({extent.x, extent.y, extent.z});
  auto code = [&](std::uint32_t f) {
    Face face = m.faces[f];
    std::sort(face.begin(), face.end());
    return morton_code(((m.positions[face[0]] + m.positions[face[1]] + m.positions[face[2]]) / 3.0 - box.min) * scale);
  };
  for (std::size_t i = 1; i < three.size(); ++i) {
    const std::uint32_t a = code(three[i - 1]), b = code(three[i]);
    ASSERT_TRUE(a < b || (a == b && three[i - 1] < three[i])) << "at " << i;
  }
}

}  // namespace
}  // namespace visimp
