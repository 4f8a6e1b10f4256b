#include "visimp/visibility/orient.h"

#include <gtest/gtest.h>

#include <random>

#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/orientation.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

Visibility measure(const Mesh& mesh) {
  const auto renderer = make_raster_renderer({200, 2});
  return compute_visibility(mesh, octahedron_cameras(2), *renderer);
}

// The same triangle on the same side, whatever its rotation.
bool same_winding(const Face& a, const Face& b) { return canonical_face(a, false) == canonical_face(b, false); }

TEST(Orient, RewindsAScanWithReversedFacesBackOutward) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  Mesh mixed = bunny;
  std::mt19937 random(3);
  std::size_t flipped = 0;
  for (Face& f : mixed.faces) {
    if (random() % 3 == 0) {
      std::swap(f[1], f[2]);
      ++flipped;
    }
  }
  const OrientResult r = orient_by_visibility(mixed, measure(mixed));
  EXPECT_EQ(r.reversed, flipped);

  EXPECT_EQ(r.seen_from_both_sides, 0u);
  for (std::size_t f = 0; f < bunny.num_faces(); ++f) ASSERT_TRUE(same_winding(r.mesh.faces[f], bunny.faces[f])) << f;
  EXPECT_EQ(analyze(r.mesh).misoriented_edges, 0u);
}

TEST(Orient, SameResultForAnyThreadCount) {
  // 40,962 vertices: more than one of the winding patches' vertex ranges (2^14), so several
  // threads really split the work.
  Mesh sphere = test::icosphere(6);
  ASSERT_GT(sphere.num_vertices(), std::size_t(1) << 15);
  std::mt19937 random(5);
  for (Face& f : sphere.faces)
    if (random() % 4 == 0) std::swap(f[1], f[2]);
  const Visibility v = measure(sphere);
  OrientOptions o;
  o.threads = 1;
  const OrientResult one = orient_by_visibility(sphere, v, o);
  EXPECT_GT(one.reversed, sphere.num_faces() / 8);
  EXPECT_EQ(analyze(one.mesh).misoriented_edges, 0u);
  for (unsigned threads : {2u, 3u}) {
    o.threads = threads;
    const OrientResult many = orient_by_visibility(sphere, v, o);
    EXPECT_EQ(many.reversed, one.reversed);
    EXPECT_EQ(many.mesh.faces, one.mesh.faces);
  }
}

TEST(Orient, LeavesFacesSeenFromBothSidesAndWindsHiddenOnesLikeTheirSurface) {
  // A square sheet (seen from above and below) and, far from it, a box sealing a sphere
  // that is wound inward: the sphere is never seen, so it is wound outward like any closed
  // surface; the sheet is left alone whichever way it faces.
  Mesh scene = test::grid(4);
  for (Face& f : scene.faces) std::swap(f[1], f[2]);  // the sheet faces down
  const std::size_t box_first = scene.num_faces();
  auto add = [&](const Mesh& m, const Vec3& at, double scale, bool inward) {
    const auto offset = static_cast<VertexIndex>(scene.num_vertices());
    for (const Vec3& p : m.positions) scene.positions.push_back(p * scale + at);
    for (const Face& f : m.faces) {
      scene.faces.push_back(inward ? Face{f[0] + offset, f[2] + offset, f[1] + offset}
                                   : Face{f[0] + offset, f[1] + offset, f[2] + offset});
    }
  };
  add(test::subdivided_cube(4), {10, 0, 0}, 4.0, false);
  const std::size_t sphere_first = scene.num_faces();
  add(test::icosphere(2), {12, 2, 2}, 1.0, true);
  const Visibility v = measure(scene);
  const OrientResult r = orient_by_visibility(scene, v);
  EXPECT_EQ(r.seen_from_both_sides, box_first);
  EXPECT_EQ(r.never_seen, scene.num_faces() - sphere_first);
  EXPECT_EQ(r.reversed, scene.num_faces() - sphere_first);  // the sphere, and nothing else
  for (std::size_t f = 0; f < sphere_first; ++f) EXPECT_EQ(r.mesh.faces[f], scene.faces[f]);
  EXPECT_GT(orientation_patches(r.mesh).signed_volume.back(), 0);
  EXPECT_EQ(analyze(r.mesh).misoriented_edges, 0u);

  Visibility wrong = v;
  wrong.face_back.pop_back();
  EXPECT_THROW(orient_by_visibility(scene, wrong), UsageError);
}

}  // namespace
}  // namespace visimp
