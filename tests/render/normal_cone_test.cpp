// The per-vertex normal cones (frame.h, VertexCone) and the cones per run of vertices
// (RenderScene::vertex_clusters): a consumer skips a vertex's work for a camera only when
// every face around it turns its back to that camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <tuple>

#include "test_meshes.h"
#include "visimp/render/frame.h"

namespace visimp {
namespace {

std::vector<std::array<float, 3>> unit_normals(const Mesh& mesh) {
  std::vector<std::array<float, 3>> normals;
  for (const Face& f : mesh.faces) {
    const Vec3 n = face_normal_unnormalized(mesh, f);
    const double length = norm(n);
    normals.push_back(length > 0 ? std::array<float, 3>{float(n.x / length), float(n.y / length), float(n.z / length)}
                                 : std::array<float, 3>{0, 0, 0});
  }
  return normals;
}

// `count` camera directions spread at random over the sphere.
std::vector<std::array<float, 3>> random_directions(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> gauss;
  std::vector<std::array<float, 3>> out;
  for (int i = 0; i < count; ++i) {
    std::array<float, 3> d{gauss(rng), gauss(rng), gauss(rng)};
    const float length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (float& c : d) c /= length;
    out.push_back(d);
  }
  return out;
}

// An icosphere with its vertices pushed in and out at random: a scan's noisy normals.
Mesh bumpy_sphere(double amplitude = 0.03) {
  Mesh m = test::icosphere(4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> bump(1 - amplitude, 1 + amplitude);
  for (Vec3& p : m.positions) p = p * bump(rng);
  return m;
}

// Several threads (each summing the corners of its own range of vertices) give the cones of
// one, bit for bit: a bumpy sphere past one range of faces, with a two-sided band of faces.
TEST(VertexCones, SameConesForAnyThreadCount) {
  Mesh mesh = test::icosphere(7);  // 327,680 faces, 163,842 vertices
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> bump(0.9995, 1.0005);  // small against its 0.01 edges
  for (Vec3& p : mesh.positions) p = p * bump(rng);
  const auto normals = unit_normals(mesh);
  RenderScene one = RenderScene::from_mesh(mesh, true), three = one;
  one.culled_faces = three.culled_faces = mesh.num_faces() - 5000;
  one.compute_normal_cones(normals, 1);
  three.compute_normal_cones(normals, 3);
  auto same = [](const NormalCone& a, const NormalCone& b) { return a.axis == b.axis && a.cutoff == b.cutoff; };
  ASSERT_EQ(one.clusters.size(), three.clusters.size());
  ASSERT_EQ(one.vertex_clusters.size(), three.vertex_clusters.size());
  ASSERT_EQ(one.vertex_cones.size(), three.vertex_cones.size());
  std::size_t skippable = 0;
  for (std::size_t c = 0; c < one.clusters.size(); ++c) ASSERT_TRUE(same(one.clusters[c], three.clusters[c])) << c;
  for (std::size_t c = 0; c < one.vertex_clusters.size(); ++c)
    ASSERT_TRUE(same(one.vertex_clusters[c], three.vertex_clusters[c])) << c;
  for (std::size_t v = 0; v < one.vertex_cones.size(); ++v) {
    ASSERT_EQ(one.vertex_cones[v].packed, three.vertex_cones[v].packed) << v;
    skippable += one.vertex_cones[v].packed[3] != -128;
  }
  EXPECT_GT(skippable, one.vertex_cones.size() / 2) << "most vertices of a bumpy sphere have a narrow cone";
}

TEST(VertexCones, SkipOnlyVerticesWhoseFacesAllTurnAway) {
  const Mesh mesh = bumpy_sphere();
  RenderScene scene = RenderScene::from_mesh(mesh, true);
  const auto normals = unit_normals(mesh);
  scene.compute_normal_cones(normals);
  ASSERT_EQ(scene.vertex_cones.size(), mesh.num_vertices());
  std::vector<std::vector<std::size_t>> faces_of(mesh.num_vertices());
  for (std::size_t t = 0; t < mesh.faces.size(); ++t) {
    for (const VertexIndex v : mesh.faces[t]) faces_of[v].push_back(t);
  }
  std::size_t skipped = 0, tested = 0;
  for (const std::array<float, 3>& d : random_directions(11, 200)) {
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v, ++tested) {
      if (!scene.vertex_cones[v].all_back_facing(d)) continue;
      ++skipped;
      for (const std::size_t t : faces_of[v]) {
        ASSERT_LT(normals[t][0] * d[0] + normals[t][1] * d[1] + normals[t][2] * d[2], 0.0f)
            << "vertex " << v << " skipped although face " << t << " faces the camera";
      }
    }
  }
  // Half of a sphere faces away from any camera; the bumps widen the cones (26% measured).
  EXPECT_GT(static_cast<double>(skipped) / static_cast<double>(tested), 0.2);
}

TEST(VertexCones, NeverSkipVerticesOfTwoSidedFaces) {
  const Mesh mesh = bumpy_sphere();
  RenderScene scene = RenderScene::from_mesh(mesh, true);
  scene.culled_faces = mesh.num_faces() / 2;  // the second half is drawn from both sides
  scene.compute_normal_cones(unit_normals(mesh));
  std::vector<bool> two_sided(mesh.num_vertices(), false);
  for (std::size_t t = scene.culled_faces; t < mesh.faces.size(); ++t) {
    for (const VertexIndex v : mesh.faces[t]) two_sided[v] = true;
  }
  for (const std::array<float, 3>& d :
       std::vector<std::array<float, 3>>{{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {-1, 0, 0}}) {
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      if (two_sided[v]) {
        EXPECT_FALSE(scene.vertex_cones[v].all_back_facing(d)) << v;
      }
    }
  }
}

TEST(VertexCones, VerticesOfOnlyDegenerateFacesAlwaysSkip) {
  Mesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};  // collinear: zero normal
  mesh.faces = {{0, 1, 2}};
  RenderScene scene = RenderScene::from_mesh(mesh, true);
  scene.compute_normal_cones(unit_normals(mesh));
  for (std::size_t v = 0; v < 3; ++v) EXPECT_TRUE(scene.vertex_cones[v].all_back_facing({0, 0, 1}));
}

// The bumpy sphere with its vertices renumbered cell by cell of a latitude-longitude grid, so
// a run of 64 consecutive vertices is a small patch (as visibility's order of first use makes it).
// Milder bumps than bumpy_sphere's: a whole patch's normals must fit in a cone under 90°.
Mesh bumpy_sphere_in_patches() {
  Mesh m = bumpy_sphere(0.005);
  std::vector<std::size_t> order(m.num_vertices());
  std::iota(order.begin(), order.end(), std::size_t{0});
  auto key = [&](std::size_t v) {
    const Vec3& p = m.positions[v];
    return std::make_tuple(std::floor(p.z * 4), std::floor(std::atan2(p.y, p.x) * 4 / M_PI), p.z);
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key(a) < key(b); });
  std::vector<VertexIndex> new_index(m.num_vertices());
  Mesh out;
  for (std::size_t i = 0; i < order.size(); ++i) {
    new_index[order[i]] = static_cast<VertexIndex>(i);
    out.positions.push_back(m.positions[order[i]]);
  }
  for (const Face& f : m.faces) out.faces.push_back({new_index[f[0]], new_index[f[1]], new_index[f[2]]});
  return out;
}

TEST(VertexClusters, SkipOnlyRunsWhoseFacesAllTurnAway) {
  const Mesh mesh = bumpy_sphere_in_patches();
  RenderScene scene = RenderScene::from_mesh(mesh, true);
  const auto normals = unit_normals(mesh);
  scene.compute_normal_cones(normals);
  constexpr std::size_t kRun = RenderScene::kClusterSize;
  ASSERT_EQ(scene.vertex_clusters.size(), (mesh.num_vertices() + kRun - 1) / kRun);
  std::size_t skipped = 0, runs = 0;
  for (const std::array<float, 3>& d : random_directions(5, 200)) {
    std::vector<bool> run_skipped(scene.vertex_clusters.size());
    for (std::size_t c = 0; c < run_skipped.size(); ++c, ++runs) {
      run_skipped[c] = scene.vertex_clusters[c].all_back_facing(d);
      skipped += run_skipped[c] ? 1 : 0;
    }
    for (std::size_t t = 0; t < mesh.faces.size(); ++t) {
      for (const VertexIndex v : mesh.faces[t]) {
        if (!run_skipped[v / kRun]) continue;
        ASSERT_LT(normals[t][0] * d[0] + normals[t][1] * d[1] + normals[t][2] * d[2], 0.0f)
            << "run " << v / kRun << " skipped although face " << t << " of its vertex " << v << " faces the camera";
      }
    }
  }
  EXPECT_GT(static_cast<double>(skipped) / static_cast<double>(runs), 0.1);
}

TEST(VertexClusters, NeverSkipRunsWithATwoSidedFace) {
  const Mesh mesh = bumpy_sphere_in_patches();
  RenderScene scene = RenderScene::from_mesh(mesh, true);
  scene.culled_faces = mesh.num_faces() / 2;
  scene.compute_normal_cones(unit_normals(mesh));
  std::vector<bool> two_sided(scene.vertex_clusters.size(), false);
  for (std::size_t t = scene.culled_faces; t < mesh.faces.size(); ++t) {
    for (const VertexIndex v : mesh.faces[t]) two_sided[v / RenderScene::kClusterSize] = true;
  }
  for (const std::array<float, 3>& d :
       std::vector<std::array<float, 3>>{{1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}}) {
    for (std::size_t c = 0; c < two_sided.size(); ++c) {
      if (two_sided[c]) {
        EXPECT_FALSE(scene.vertex_clusters[c].all_back_facing(d)) << c;
      }
    }
  }
}

}  // namespace
}  // namespace visimp
