#include "visimp/visibility/visibility.h"

#include <gtest/gtest.h>

#include <type_traits>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numeric>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/union_find.h"
#include "visimp/core/validate.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

// A job keeps a reference to its mesh: building one from a temporary must not compile.
static_assert(std::is_constructible_v<VisibilityJob, const Mesh&, int, const VisibilityOptions&>);
static_assert(!std::is_constructible_v<VisibilityJob, Mesh&&, int, const VisibilityOptions&>);

Visibility measure(const Mesh& mesh, int resolution = 256, const VisibilityOptions& options = {},
                   const CameraSet& cameras = octahedron_cameras(2), unsigned threads = 2) {
  const auto renderer = make_raster_renderer({resolution, threads});
  return compute_visibility(mesh, cameras, *renderer, options);
}

Mesh translated(Mesh m, const Vec3& by, bool flip = false) {
  for (Vec3& p : m.positions) p += by;
  if (flip)
    for (Face& f : m.faces) std::swap(f[1], f[2]);
  return m;
}

Mesh scaled(Mesh m, double s) {
  for (Vec3& p : m.positions) p *= s;
  return m;
}

// Appends b to a, returning the index of b's first face.
std::size_t append(Mesh& a, const Mesh& b) {
  const auto offset = static_cast<VertexIndex>(a.positions.size());
  const std::size_t first = a.faces.size();
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (Face f : b.faces) a.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  return first;
}

TEST(Visibility, ConvexMeshIsFullyVisibleEverywhere) {
  // Eq. 3.1: every point of a convex object is seen by every camera in front of it.
  for (const Mesh& m : {test::icosphere(3), test::subdivided_cube(4)}) {
    const Visibility v = measure(m);
    for (std::size_t f = 0; f < v.face.size(); ++f) ASSERT_NEAR(v.face[f], 1.0, 0.01) << "face " << f;
    EXPECT_NEAR(v.mesh, 1.0, 0.005);
    EXPECT_TRUE(v.stats.back_faces_culled);
  }
}

TEST(Visibility, SphereSealedInABoxIsInvisible) {
  // A closed box of side 4 around a detailed sphere of radius 1: no camera sees the sphere.
  Mesh scene = translated(scaled(test::subdivided_cube(6), 4.0), {-2, -2, -2});
  const std::size_t sphere_first = append(scene, test::icosphere(4));
  const Visibility v = measure(scene);
  for (std::size_t f = sphere_first; f < scene.num_faces(); ++f) ASSERT_EQ(v.face[f], 0.0f) << "sphere face " << f;
  for (std::size_t f = 0; f < sphere_first; ++f) ASSERT_GT(v.face[f], 0.99f) << "box face " << f;
}

TEST(DropHidden, RemovesExactlyTheNeverSeenFacesAndLeavesAValidMesh) {
  Mesh scene = translated(scaled(test::subdivided_cube(6), 4.0), {-2, -2, -2});
  const std::size_t sphere_first = append(scene, test::icosphere(3));
  scene.face_quality.assign(scene.num_faces(), 0.5f);
  const Visibility v = measure(scene);
  const HiddenRemoval r = drop_hidden_faces(scene, v.face, 0.0);
  // The box, and nothing else, survives: same faces, same positions, in input order.
  EXPECT_EQ(r.faces_removed, scene.num_faces() - sphere_first);
  ASSERT_EQ(r.mesh.num_faces(), sphere_first);
  const Mesh box = translated(scaled(test::subdivided_cube(6), 4.0), {-2, -2, -2});
  EXPECT_TRUE(r.mesh.faces == box.faces);
  EXPECT_TRUE(r.mesh.positions == box.positions);
  EXPECT_EQ(r.mesh.face_quality.size(), r.mesh.num_faces());
  EXPECT_NO_THROW(require_valid(r.mesh, "dropped"));
  const double sphere_area = analyze(test::icosphere(3)).area, box_area = analyze(box).area;
  EXPECT_NEAR(r.area_removed, sphere_area, 1e-9);
  EXPECT_NEAR(r.area_fraction_removed, sphere_area / (sphere_area + box_area), 1e-12);
  // A threshold keeps only faces above it; bad thresholds and sizes are usage errors.
  std::vector<float> graded(scene.num_faces(), 0.3f);
  graded[0] = 0.9f;
  EXPECT_EQ(drop_hidden_faces(scene, graded, 0.5).mesh.num_faces(), 1u);
  EXPECT_THROW(drop_hidden_faces(scene, graded, 1.0), UsageError);
  EXPECT_THROW(drop_hidden_faces(scene, {}, 0.0), UsageError);
}

TEST(Visibility, InsideOfABowlIsLessVisibleThanOutside) {
  // An open bowl: the lower half of a sphere (outside faces point outward) and a smaller
  // lower half facing inward (the inside of the bowl).
  auto lower_half = [](const Mesh& sphere) {
    Mesh half = sphere;
    half.faces.clear();
    for (const Face& f : sphere.faces) {
      if (sphere.positions[f[0]].z + sphere.positions[f[1]].z + sphere.positions[f[2]].z < 0) half.faces.push_back(f);
    }
    return half;
  };
  Mesh bowl = lower_half(test::icosphere(4));
  const std::size_t inside_first = append(bowl, translated(lower_half(test::icosphere(4, 0.9)), {}, true));
  const Visibility v = measure(bowl);
  EXPECT_FALSE(v.stats.back_faces_culled);
  double outside = 0, inside = 0;
  for (std::size_t f = 0; f < inside_first; ++f) outside += v.face[f];
  for (std::size_t f = inside_first; f < bowl.num_faces(); ++f) inside += v.face[f];
  outside /= static_cast<double>(inside_first);
  inside /= static_cast<double>(bowl.num_faces() - inside_first);
  EXPECT_GT(outside, 0.95);
  EXPECT_LT(inside, outside - 0.2);
  EXPECT_GT(inside, 0.2);  // the opening lets the upper cameras in
}

TEST(Visibility, DepthTestRescuesSubPixelFaces) {
  // 81920 faces at 64×64: nearly every face is smaller than a pixel and owns none. The
  // depth test still finds them visible; pixel ownership alone visibly fails.
  const Mesh sphere = test::icosphere(6);
  const Visibility with = measure(sphere, 64);
  EXPECT_GT(with.mesh, 0.98);
  VisibilityOptions no_test;
  no_test.depth_test = false;
  const Visibility without = measure(sphere, 64, no_test);
  EXPECT_LT(without.mesh, 0.5);
}

TEST(Visibility, SameBitsForAnyThreadCount) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  const Visibility one = measure(bunny, 200, {}, octahedron_cameras(2), 1);
  const Visibility three = measure(bunny, 200, {}, octahedron_cameras(2), 3);
  EXPECT_EQ(one.face, three.face);
  EXPECT_EQ(one.vertex, three.vertex);
}

// Preparing and finishing on several threads (VisibilityOptions::threads) changes nothing: a
// closed sphere (one-sided faces) beside a fine open sheet (two-sided), many ranges of faces
// each, and a coarse plate whose edges are long at 96 px: with and without refinement, the
// same V, sides and counts on 1 and 3 threads.
TEST(Visibility, SameResultForAnyPreparingThreadCount) {
  Mesh scene = test::icosphere(6);  // 81,920 faces
  append(scene, translated(scaled(test::grid(120), 0.02), {1.5, 0, 0}));
  append(scene, translated(scaled(test::grid(3), 0.8), {-1, -1, -1.5}));
  for (const bool refine : {false, true}) {
    VisibilityOptions one, three;
    one.refine = three.refine = refine;
    one.threads = 1;
    three.threads = 3;
    const Visibility a = measure(scene, 96, one), b = measure(scene, 96, three);
    EXPECT_EQ(a.stats.two_sided_faces, 2u * 120 * 120 + 2 * 3 * 3);
    EXPECT_EQ(a.stats.refinement_rounds > 0, refine) << "the sheet's faces must be long at 96 px";
    EXPECT_EQ(a.face, b.face);
    EXPECT_EQ(a.face_front, b.face_front);
    EXPECT_EQ(a.face_back, b.face_back);
    EXPECT_EQ(a.vertex, b.vertex);
    EXPECT_EQ(a.mesh, b.mesh);
    EXPECT_EQ(a.stats.one_sided_faces, b.stats.one_sided_faces);
    EXPECT_EQ(a.stats.seen_from_behind, b.stats.seen_from_behind);
    EXPECT_EQ(a.stats.hidden_faces, b.stats.hidden_faces);
  }
}

// The tallies against their definition: total = Σ over cameras of q(R·N) per side, the same
// for one worker and three (whose batches of 8 frames end at other cameras), on an open bowl,
// whose faces are tallied from both sides. Within one unit of q per camera: the test's normal
// is computed from the scene's float positions, the library's from the input's doubles.
TEST(Visibility, TotalsAreTheSumOfEveryCamerasWeightPerSide) {
  const Mesh sphere = test::icosphere(3);
  Mesh bowl;
  bowl.positions = sphere.positions;
  for (const Face& f : sphere.faces) {
    if (sphere.positions[f[0]].z + sphere.positions[f[1]].z + sphere.positions[f[2]].z < 1.5) bowl.faces.push_back(f);
  }
  const CameraSet cameras = octahedron_cameras(2);  // 66: several batches and a partial one
  const VisibilityJob job(bowl, 128, {});
  const VisibilityTally one = job.render(cameras, 0, cameras.size(), *make_raster_renderer({128, 1}));
  const VisibilityTally three = job.render(cameras, 0, cameras.size(), *make_raster_renderer({128, 3}));
  EXPECT_EQ(one.seen, three.seen);
  EXPECT_EQ(one.total, three.total);
  EXPECT_EQ(one.seen_back, three.seen_back);
  EXPECT_EQ(one.total_back, three.total_back);

  const RenderScene& scene = job.scene();
  const std::size_t one_sided = one.key.one_sided_faces;
  ASSERT_LT(one_sided, scene.faces.size()) << "the bowl is open: its faces are two-sided";
  ASSERT_EQ(one.total_back.size(), scene.faces.size() - one_sided);
  for (std::size_t t = 0; t < scene.faces.size(); ++t) {
    const Face& f = scene.faces[t];
    auto at = [&](int k) {
      const auto& p = scene.positions[f[k]];
      return Vec3(p[0], p[1], p[2]);
    };
    const Vec3 n = cross(at(1) - at(0), at(2) - at(0));
    std::int64_t front = 0, back = 0;
    for (const Vec3& d : cameras.directions) {
      const auto cosine = static_cast<float>(dot(n, d) / (norm(n) * norm(d)));
      front += quantize_weight(cosine);
      back += quantize_weight(-cosine);
    }
    const auto count = static_cast<std::int64_t>(cameras.size());
    ASSERT_LE(std::abs(front - std::int64_t{one.total[t]}), count) << "face " << t;
    if (t >= one_sided) {
      ASSERT_LE(std::abs(back - std::int64_t{one.total_back[t - one_sided]}), count) << "face " << t;
    }
    ASSERT_LE(one.seen[t], one.total[t]);
  }
}

TEST(Visibility, MergedSlicesEqualOneRun) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  const CameraSet cameras = octahedron_cameras(2);
  const auto renderer = make_raster_renderer({160, 2});
  const VisibilityJob job(bunny, 160, {});
  const VisibilityTally all = job.render(cameras, 0, cameras.size(), *renderer);
  VisibilityTally a = job.render(cameras, 40, 66, *renderer);
  const VisibilityTally b = job.render(cameras, 0, 17, *renderer);
  const VisibilityTally c = job.render(cameras, 17, 40, *renderer);
  EXPECT_THROW(job.finish(a), UsageError);  // incomplete
  a.merge(b);
  EXPECT_THROW(a.merge(b), UsageError);  // cameras 0..17 twice
  a.merge(c);
  ASSERT_TRUE(a.complete());
  EXPECT_EQ(a.seen, all.seen);
  EXPECT_EQ(a.total, all.total);
  EXPECT_EQ(job.finish(a).face, job.finish(all).face);

  // Through a file and back.
  const test::TempDir temp("tally");
  const std::string path = temp.path() + "/all.bin";
  all.write(path);
  const VisibilityTally back = VisibilityTally::read(path);
  EXPECT_EQ(back.seen, all.seen);
  EXPECT_EQ(back.key, all.key);
  // A tally of another camera set does not merge.
  VisibilityTally other = job.render(octahedron_cameras(1), 0, 18, *renderer);
  EXPECT_THROW(other.merge(all), UsageError);
}

TEST(Refinement, SplitsUntilEdgesAreShortAndKeepsTheSurface) {
  const Mesh cube = test::subdivided_cube(1);                    // 12 faces, edges 1 and √2
  EXPECT_FALSE(refine_long_edges(cube, 2.0, 1000).has_value());  // nothing to do: skipped
  const auto refined = refine_long_edges(cube, 0.3, 100000);
  ASSERT_TRUE(refined.has_value());
  const Mesh& m = refined->mesh;
  for (const Face& f : m.faces)
    for (int i = 0; i < 3; ++i) ASSERT_LE(norm(m.positions[f[i]] - m.positions[f[(i + 1) % 3]]), 0.3);
  const MeshStats before = analyze(cube), after = analyze(m);
  EXPECT_TRUE(after.closed_manifold());  // conforming: no cracks
  EXPECT_EQ(after.misoriented_edges, 0u);
  EXPECT_NEAR(after.area, before.area, 1e-12);
  // Each input face's sub-faces add up to its area.
  std::vector<double> area(cube.num_faces(), 0.0);
  for (std::size_t t = 0; t < m.num_faces(); ++t)
    area[refined->input_face[t]] += 0.5 * norm(face_normal_unnormalized(m, m.faces[t]));
  for (double a : area) EXPECT_NEAR(a, 0.5, 1e-12);
  EXPECT_THROW(refine_long_edges(cube, 1e-3, 1000), UsageError);  // over budget
}

TEST(Visibility, LargeFacesAreRefinedAndDegenerateFacesGetAValue) {
  // A 2-face square with a zero-area face glued to it.
  Mesh m = test::grid(1);
  m.positions.push_back({0.5, 0, 0});
  m.faces.push_back({0, 1, 4});  // collinear
  const Visibility v = measure(m, 64);
  EXPECT_GT(v.stats.refined_faces, 100u);
  EXPECT_EQ(v.stats.degenerate_faces, 1u);
  for (float x : v.face) {
    EXPECT_TRUE(std::isfinite(x));
    EXPECT_GT(x, 0.99f);  // a lone flat square is seen from its whole front hemisphere
  }
}

TEST(Visibility, FractionalModeIsBetweenZeroAndBinary) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  VisibilityOptions fractional;
  fractional.fractional = true;
  const Visibility binary = measure(bunny, 200), frac = measure(bunny, 200, fractional);
  EXPECT_LE(frac.mesh, binary.mesh + 1e-9);
  EXPECT_GT(frac.mesh, 0.5);
}

// Area-weighted mean V per connected component, largest component first.
std::vector<std::pair<double, double>> component_area_and_visibility(const Mesh& mesh, const std::vector<float>& v) {
  UnionFind sets(mesh.num_vertices());
  for (const Face& f : mesh.faces) {
    sets.unite(f[0], f[1]);
    sets.unite(f[0], f[2]);
  }
  std::map<std::uint32_t, std::pair<double, double>> sums;  // root → (area, area·V)
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const double area = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    auto& s = sums[sets.find(mesh.faces[f][0])];
    s.first += area;
    s.second += area * v[f];
  }
  std::vector<std::pair<double, double>> out;
  for (const auto& [root, s] : sums) out.emplace_back(s.first, s.first > 0 ? s.second / s.first : 0.0);
  std::sort(out.rbegin(), out.rend());
  return out;
}

TEST(Visibility, RealMeshesGiveFiniteValues) {
  std::size_t measured = 0;
  std::string absent;
  for (const std::string& path : test::real_mesh_paths()) {
    if (!std::filesystem::exists(path)) {
      absent += " " + path;
      continue;
    }
    ++measured;
    const Mesh mesh = read_mesh(path);
    const Visibility v = measure(mesh, 256);
    ASSERT_EQ(v.face.size(), mesh.num_faces());
    for (float x : v.face) ASSERT_TRUE(std::isfinite(x) && x >= 0 && x <= 1) << path;
    for (float x : v.vertex) ASSERT_TRUE(std::isfinite(x) && x >= 0 && x <= 1) << path;
    EXPECT_GT(v.mesh, 0.1) << path;
  }
  if (!absent.empty()) std::cout << "[ note ] absent (../shared/meshes), not measured:" << absent << "\n";
  if (measured == 0) GTEST_SKIP() << "every real mesh is absent:" << absent;
}

TEST(Visibility, CadInteriorsComeOutInvisible) {
  // meshes/SOURCES.md: the ESP module hides a board slab under its shield (15.9% of the area).
  const std::string esp = test::bundled_mesh("kicad_esp_wroom02.ply");
  const Visibility v = measure(read_mesh(esp), 480, {}, octahedron_cameras(3));
  EXPECT_NEAR(v.stats.hidden_area_fraction, 0.159, 0.015);
}

TEST(Visibility, EnclosedCadComponentsComeOutInvisible) {
  // meshes/SOURCES.md: the snap-in capacitor and the D-sub connector (../shared/meshes) each
  // enclose a whole second component (14.0% and 10.4% of the area).
  std::size_t measured = 0;
  std::string absent;
  for (const char* name : {"kicad_cap_snapin_d40.ply", "kicad_dsub62_male.ply"}) {
    const std::string path = test::shared_mesh(name);
    if (!std::filesystem::exists(path)) {
      absent += " " + path;
      continue;
    }
    ++measured;
    const Mesh mesh = read_mesh(path);
    const auto parts = component_area_and_visibility(mesh, measure(mesh, 480, {}, octahedron_cameras(3)).face);
    ASSERT_EQ(parts.size(), 2u) << name;
    EXPECT_GT(parts[0].second, 0.6) << name;   // the outside
    EXPECT_LT(parts[1].second, 0.05) << name;  // the enclosed part: V ~ 0
  }
  if (!absent.empty()) std::cout << "[ note ] absent (../shared/meshes), not measured:" << absent << "\n";
  if (measured == 0) GTEST_SKIP() << "both meshes are absent:" << absent;
}

}  // namespace
}  // namespace visimp
