// The per-vertex normal cones (frame.h, VertexCone): a consumer skips a vertex's work for a
// camera only when every face around it turns its back to that camera.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

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

// An icosphere with its vertices pushed in and out at random: a scan's noisy normals.
Mesh bumpy_sphere() {
  Mesh m = test::icosphere(4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> bump(0.97, 1.03);
  for (Vec3& p : m.positions) p = p * bump(rng);
  return m;
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
  std::mt19937 rng(11);
  std::normal_distribution<float> gauss;
  std::size_t skipped = 0, tested = 0;
  for (int camera = 0; camera < 200; ++camera) {
    std::array<float, 3> d{gauss(rng), gauss(rng), gauss(rng)};
    const float length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (float& c : d) c /= length;
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

}  // namespace
}  // namespace visimp
