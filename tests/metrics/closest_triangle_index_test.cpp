#include "closest_triangle_index.h"

#include <gtest/gtest.h>

#include <random>

#include "test_meshes.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

double brute_force_squared_distance(const Mesh& m, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Face& f : m.faces) {
    if (is_degenerate(m, f)) continue;
    const Vec3& a = m.positions[f[0]];
    best = std::min(best, point_triangle_squared_distance(p, a, m.positions[f[1]] - a, m.positions[f[2]] - a));
  }
  return best;
}

// Every Voronoi region of a triangle against hand-computed distances.
TEST(ClosestTriangleIndex, PointTriangleDistanceInEachRegion) {
  const Vec3 a{0, 0, 0}, ab{2, 0, 0}, ac{0, 2, 0};
  EXPECT_DOUBLE_EQ(point_triangle_squared_distance({0.5, 0.5, 3}, a, ab, ac), 9.0);  // interior
  EXPECT_DOUBLE_EQ(point_triangle_squared_distance({-1, -1, 0}, a, ab, ac), 2.0);    // vertex a
  EXPECT_DOUBLE_EQ(point_triangle_squared_distance({3, -1, 0}, a, ab, ac), 2.0);     // vertex b
  EXPECT_DOUBLE_EQ(point_triangle_squared_distance({-1, 3, 0}, a, ab, ac), 2.0);     // vertex c
  EXPECT_DOUBLE_EQ(point_triangle_squared_distance({1, -2, 0}, a, ab, ac), 4.0);     // edge ab
  EXPECT_DOUBLE_EQ(point_triangle_squared_distance({-2, 1, 1}, a, ab, ac), 5.0);     // edge ac
  EXPECT_NEAR(point_triangle_squared_distance({2, 2, 0}, a, ab, ac), 2.0, 1e-15);    // edge bc
}

// The tree must give exactly the brute-force answer, whatever the hint: the hint only
// changes how fast the answer is found.
void expect_matches_brute_force(const Mesh& m, double spread, std::uint32_t seed, unsigned threads = 1) {
  const ClosestTriangleIndex index(m, threads);
  ASSERT_FALSE(index.empty());
  const BoundingBox box = bounding_box(m);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-spread, 1 + spread);
  std::uniform_int_distribution<std::uint32_t> any(0, static_cast<std::uint32_t>(m.num_faces() - 1));
  std::uint32_t chained = ClosestTriangleIndex::kNoHint;
  for (int i = 0; i < 400; ++i) {
    const Vec3 p{box.min.x + u(rng) * (box.max.x - box.min.x), box.min.y + u(rng) * (box.max.y - box.min.y),
                 box.min.z + u(rng) * (box.max.z - box.min.z)};
    const double expected = brute_force_squared_distance(m, p);
    std::uint32_t none = ClosestTriangleIndex::kNoHint, random = any(rng);
    EXPECT_EQ(index.squared_distance(p, none), expected);
    EXPECT_EQ(index.squared_distance(p, random), expected);
    EXPECT_EQ(index.squared_distance(p, chained), expected);
  }
}

TEST(ClosestTriangleIndex, MatchesBruteForceAroundARealMesh) {
  expect_matches_brute_force(read_mesh(test::bundled_mesh("bunny.ply")), 0.3, 1);
}

TEST(ClosestTriangleIndex, MatchesBruteForceFarFromTheOriginAndAtTinyScale) {
  Mesh far = test::icosphere(3), tiny = test::icosphere(3);
  for (Vec3& p : far.positions) p += Vec3{1e7, -3e7, 2e7};
  for (Vec3& p : tiny.positions) p *= 1e-9;
  expect_matches_brute_force(far, 2.0, 2);
  expect_matches_brute_force(tiny, 2.0, 3);
}

// Above kParallelTriangles the two halves of a node are built on two threads, each into the
// slots counted for it in advance (subtree_nodes): a miscounted slot leaves nodes or triangles
// unwritten or overwritten, and the answers wrong. 81,920 faces, on one thread and on four.
TEST(ClosestTriangleIndex, MatchesBruteForceWhenBuiltOnSeveralThreads) {
  const Mesh sphere = test::icosphere(6);
  ASSERT_GT(sphere.num_faces(), 65536u);
  expect_matches_brute_force(sphere, 0.2, 4, 1);
  expect_matches_brute_force(sphere, 0.2, 5, 4);
  // The same tree: the nearest triangle's number (its place in leaf order) and the distance
  // agree for every query, ties included (both searches take the same path).
  const ClosestTriangleIndex one(sphere, 1), four(sphere, 4);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1.3, 1.3);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    std::uint32_t hint_one = ClosestTriangleIndex::kNoHint, hint_four = ClosestTriangleIndex::kNoHint;
    ASSERT_EQ(one.squared_distance(p, hint_one), four.squared_distance(p, hint_four)) << i;
    ASSERT_EQ(hint_one, hint_four) << i;
  }
}

// For a running maximum: above the bound the answer is exact; at or below it, any value up to
// the bound will do (max(bound, answer) is unchanged), and a bound past every distance needs no
// search. A running maximum over many points equals the maximum of exact queries.
TEST(ClosestTriangleIndex, DistancePastABoundKeepsARunningMaximumExact) {
  const Mesh m = read_mesh(test::bundled_mesh("bunny.ply"));
  const ClosestTriangleIndex index(m, 1);
  const BoundingBox box = bounding_box(m);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  std::uint32_t hint = ClosestTriangleIndex::kNoHint, exact_hint = ClosestTriangleIndex::kNoHint;
  double running = 0, exact_max = 0;
  std::size_t below = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p{box.min.x + u(rng) * (box.max.x - box.min.x), box.min.y + u(rng) * (box.max.y - box.min.y),
                 box.min.z + u(rng) * (box.max.z - box.min.z)};
    const double exact = index.squared_distance(p, exact_hint);
    ASSERT_EQ(exact, brute_force_squared_distance(m, p));
    const double past = index.squared_distance_past(p, hint, running);
    if (exact > running)
      EXPECT_EQ(past, exact) << i;
    else
      EXPECT_LE(past, running) << i;
    below += exact <= running;
    running = std::max(running, past);
    exact_max = std::max(exact_max, exact);
    ASSERT_EQ(running, exact_max) << i;
  }
  EXPECT_GT(below, 1000u);  // the maximum settles early: most points are at or below it
}

TEST(ClosestTriangleIndex, SkipsDegenerateFaces) {
  Mesh m = test::grid(3);
  m.faces.push_back({0, 0, 1});  // repeated index: no area, must not be indexed
  m.positions.push_back({5, 5, 5});
  m.positions.push_back({5, 5, 5});
  m.positions.push_back({5, 5, 5});
  const auto n = static_cast<VertexIndex>(m.positions.size());
  m.faces.push_back({n - 3, n - 2, n - 1});  // a point-like face far away
  const ClosestTriangleIndex index(m);
  std::uint32_t hint = ClosestTriangleIndex::kNoHint;
  EXPECT_GT(index.squared_distance({5, 5, 5}, hint), 1.0);
  EXPECT_TRUE(ClosestTriangleIndex(Mesh{}).empty());
}

}  // namespace
}  // namespace visimp
