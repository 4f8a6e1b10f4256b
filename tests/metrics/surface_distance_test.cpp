#include "visimp/metrics/surface_distance.h"

#include <gtest/gtest.h>

// The kernel before distance.h: its bounded-error code calls CGAL::midpoint by qualified name.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Surface_mesh.h>

#include <fstream>

#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/metrics/bounded_hausdorff.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

TEST(SurfaceDistance, MeshAgainstItselfIsZero) {
  const Mesh s = test::icosphere(2);
  const SurfaceDistance d = surface_distance(s, s);
  EXPECT_NEAR(d.hausdorff, 0, 1e-12);
  EXPECT_NEAR(d.rms, 0, 1e-12);
}

TEST(SurfaceDistance, ParallelPlanesAreTheirSeparationApart) {
  const Mesh a = test::grid(4);
  Mesh b = a;
  for (Vec3& p : b.positions) p.z += 0.25;
  const SurfaceDistance d = surface_distance(a, b);
  EXPECT_NEAR(d.a_to_b.max, 0.25, 1e-12);
  EXPECT_NEAR(d.a_to_b.mean, 0.25, 1e-12);
  EXPECT_NEAR(d.rms, 0.25, 1e-12);
  EXPECT_NEAR(d.diagonal, std::sqrt(32.0), 1e-12);
}

TEST(SurfaceDistance, ConcentricSpheresDifferByTheRadii) {
  const Mesh a = test::icosphere(4, 1.0), b = test::icosphere(4, 1.1);
  const SurfaceDistance d = surface_distance(a, b);
  // Facets sit inside their sphere by at most r(1 - cos(edge/2r)) ≈ 0.3%: allow that.
  EXPECT_NEAR(d.hausdorff, 0.1, 0.005);
  EXPECT_NEAR(d.rms, 0.1, 0.005);
}

TEST(SurfaceDistance, SameNumbersForAnyThreadCount) {
  const Mesh a = test::icosphere(3, 1.0), b = test::icosphere(2, 1.0);
  SurfaceDistanceOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const SurfaceDistance d1 = surface_distance(a, b, one), d2 = surface_distance(a, b, two);
  EXPECT_EQ(d1.hausdorff, d2.hausdorff);
  EXPECT_EQ(d1.rms, d2.rms);
  EXPECT_EQ(d1.a_to_b.mean, d2.a_to_b.mean);
}

void expect_same_distance(const SurfaceDistance& x, const SurfaceDistance& y) {
  EXPECT_EQ(x.hausdorff, y.hausdorff);
  EXPECT_EQ(x.rms, y.rms);
  EXPECT_EQ(x.diagonal, y.diagonal);
  for (auto d : {&SurfaceDistance::a_to_b, &SurfaceDistance::b_to_a}) {
    EXPECT_EQ((x.*d).max, (y.*d).max);
    EXPECT_EQ((x.*d).mean, (y.*d).mean);
    EXPECT_EQ((x.*d).samples, (y.*d).samples);
    EXPECT_EQ((x.*d).histogram, (y.*d).histogram);
  }
  EXPECT_EQ(x.visible.rms, y.visible.rms);
  EXPECT_EQ(x.vertex_error, y.vertex_error);
  EXPECT_EQ(x.face_error, y.face_error);
}

TEST(SurfaceDistance, AKeptReferenceGivesTheSameNumbersAsSeparateCalls) {
  // Against coarser, finer (more faces than A: the default sample counts follow B) and
  // shifted surfaces, with options that change the plan between calls.
  const Mesh a = test::icosphere(3, 1.0);
  Mesh shifted = test::icosphere(2, 1.0);
  for (Vec3& p : shifted.positions) p.x += 0.05;
  const Mesh others[] = {test::icosphere(2, 1.0), test::icosphere(4, 1.02), shifted, test::icosphere(1, 0.9)};
  SurfaceDistanceOptions fixed;
  fixed.samples = 5000;
  fixed.face_visibility.assign(a.num_faces(), 0.5f);
  fixed.vertex_errors = true;
  SurfaceDistanceOptions other_seed = fixed;
  other_seed.seed = 7;
  const SurfaceDistanceReference reference(a);
  for (const SurfaceDistanceOptions& options : {fixed, SurfaceDistanceOptions{}, other_seed, fixed}) {
    for (const Mesh& b : others) {
      SCOPED_TRACE(std::to_string(b.num_faces()) + " faces, seed " + std::to_string(options.seed));
      const SurfaceDistance kept = reference.distance_to(b, options), alone = surface_distance(a, b, options);
      EXPECT_GT(alone.hausdorff, 0.0);
      expect_same_distance(kept, alone);
    }
  }
}

TEST(SurfaceDistance, TranslatedCopyIsTheTranslationAway) {
  // Every point of the moved sphere is exactly |t| from its own original, so no sample can
  // be farther; the points moving straight out are nearly |t| from the surface.
  const Mesh a = test::icosphere(4);
  Mesh b = a;
  const Vec3 t{0.02, -0.01, 0.015};
  for (Vec3& p : b.positions) p += t;
  const SurfaceDistance d = surface_distance(a, b);
  EXPECT_LE(d.hausdorff, norm(t) * (1 + 1e-12));
  EXPECT_GE(d.hausdorff, 0.95 * norm(t));
}

TEST(SurfaceDistance, HistogramCoversTheAreaAndEdgesAddToTheMaximumOnly) {
  const Mesh a = test::icosphere(3), b = test::icosphere(1);
  SurfaceDistanceOptions options;
  options.histogram_bins = 7;
  const SurfaceDistance d = surface_distance(a, b, options);
  ASSERT_EQ(d.a_to_b.histogram.size(), 7u);
  double total = 0;
  for (double h : d.a_to_b.histogram) total += h;
  EXPECT_NEAR(total, 1.0, 1e-9);
  EXPECT_GT(d.a_to_b.histogram.back(), 0.0);           // the bin holding the maximum
  EXPECT_GT(d.a_to_b.samples, d.a_to_b.face_samples);  // vertices and edges were sampled too
}

// Vertex and edge samples count only through their maximum. With error maps A's vertices are
// measured one by one; without them (and for B's vertices and all edges) a block's running
// maximum lets most samples skip the search. The numbers must be the same either way (few face
// samples and many edge samples: the vertices and edges weigh in the maximum).
TEST(SurfaceDistance, VertexAndEdgeMaximaAreTheSameWithAndWithoutErrorMaps) {
  const Mesh a = test::icosphere(3), b = test::icosphere(1);
  SurfaceDistanceOptions options;
  options.samples = 50;
  options.edge_samples = 20000;
  const SurfaceDistance plain = surface_distance(a, b, options);
  options.vertex_errors = true;
  const SurfaceDistance mapped = surface_distance(a, b, options);
  EXPECT_EQ(plain.a_to_b.max, mapped.a_to_b.max);
  EXPECT_EQ(plain.b_to_a.max, mapped.b_to_a.max);
  EXPECT_EQ(plain.hausdorff, mapped.hausdorff);
  EXPECT_EQ(plain.rms, mapped.rms);
  EXPECT_EQ(plain.a_to_b.samples, mapped.a_to_b.samples);
  float vertex_max = 0;
  for (float e : mapped.vertex_error) vertex_max = std::max(vertex_max, e);
  EXPECT_GT(vertex_max, 0.0f);
  EXPECT_LE(vertex_max, static_cast<float>(plain.a_to_b.max));
}

TEST(SurfaceDistance, VisibilityWeightingFollowsV) {
  // Two planes 0.25 apart, except that half of A (x < 2) is bent further away; with V = 0 on
  // that half the visible numbers see only the flat half.
  Mesh a = test::grid(4);
  for (Vec3& p : a.positions)
    if (p.x < 2) p.z = -0.5 * (2 - p.x);
  Mesh b = test::grid(4);
  for (Vec3& p : b.positions) p.z += 0.25;
  SurfaceDistanceOptions options;
  options.face_visibility.assign(a.num_faces(), 1.0f);
  const SurfaceDistance all_visible = surface_distance(a, b, options);
  EXPECT_DOUBLE_EQ(all_visible.visible.rms, all_visible.a_to_b.rms);
  // The visible maximum is over face samples; the plain one also over vertices and edges.
  EXPECT_LE(all_visible.visible.max, all_visible.a_to_b.max);
  EXPECT_GE(all_visible.visible.max, 0.95 * all_visible.a_to_b.max);
  for (std::size_t f = 0; f < a.num_faces(); ++f) {
    const Face& face = a.faces[f];
    const double x = (a.positions[face[0]].x + a.positions[face[1]].x + a.positions[face[2]].x) / 3;
    options.face_visibility[f] = x < 2 ? 0.0f : 1.0f;
  }
  const SurfaceDistance half = surface_distance(a, b, options);
  EXPECT_NEAR(half.visible.mean, 0.25, 1e-9);
  EXPECT_NEAR(half.visible.max, 0.25, 1e-9);
  EXPECT_GT(half.a_to_b.max, 0.9);
  EXPECT_THROW(surface_distance(test::grid(2), b, options), InvalidMeshError);  // not one V per face of A
  a.face_quality.assign(a.num_faces(), 0.0f);                                   // quality is not V: it changes nothing
  EXPECT_DOUBLE_EQ(surface_distance(a, b, options).visible.mean, half.visible.mean);
}

TEST(SurfaceDistance, AgreesWithCgalHausdorffOnARealPair) {
  const std::string dir = std::string(VISIMP_SHARED_MESHES_DIR) + "/../metro-ref";
  for (const char* name : {"/bunny.ply", "/bunny_s10.ply"})
    if (!std::ifstream(dir + name)) GTEST_SKIP() << dir << name << " is absent (../shared/metro-ref)";
  const Mesh a = read_mesh(dir + "/bunny.ply"), b = read_mesh(dir + "/bunny_s10.ply");
  SurfaceDistanceOptions options;
  options.samples = 1000000;
  const SurfaceDistance ours = surface_distance(a, b, options);
  namespace PMP = CGAL::Polygon_mesh_processing;
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  auto to_cgal = [](const Mesh& m) {
    CGAL::Surface_mesh<K::Point_3> sm;
    std::vector<CGAL::Surface_mesh<K::Point_3>::Vertex_index> v;
    for (const Vec3& p : m.positions) v.push_back(sm.add_vertex(K::Point_3(p.x, p.y, p.z)));
    for (const Face& f : m.faces) sm.add_face(v[f[0]], v[f[1]], v[f[2]]);
    return sm;
  };
  const auto ca = to_cgal(a), cb = to_cgal(b);
  // CGAL's bounded-error Hausdorff is the reference: within `bound` of the true value, and
  // deterministic (its sampled approximate_Hausdorff_distance reseeds from the clock, which
  // made this comparison flaky). A sampled maximum can only undershoot the truth.
  const double bound = 1e-5 * ours.diagonal;
  const double truth = PMP::bounded_error_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(ca, cb, bound);
  EXPECT_LE(ours.hausdorff, truth + bound) << "CGAL " << truth;
  EXPECT_GE(ours.hausdorff, 0.99 * truth) << "CGAL " << truth;  // 1M samples reach 99.5%
}

TEST(SurfaceDistance, StratifiedSamplesCoverEveryFaceExactlyOnce) {
  // Planes 0.25 apart: every stratified sample lies on A (distance exactly 0.25 to B) and
  // the cells of each face add up to its area.
  const Mesh a = test::grid(4);
  Mesh b = a;
  for (Vec3& p : b.positions) p.z += 0.25;
  SurfaceDistanceOptions options;
  options.sampling = FaceSampling::stratified;
  options.samples = 3200;  // 100 per face: a 10 x 10 split
  const SurfaceDistance d = surface_distance(a, b, options);
  EXPECT_NEAR(d.a_to_b.max, 0.25, 1e-12);
  EXPECT_NEAR(d.a_to_b.mean, 0.25, 1e-12);
  EXPECT_NEAR(d.a_to_b.area, 16.0, 1e-9);
  EXPECT_EQ(d.a_to_b.face_samples, 3200u);
  // Against itself a stratified sample never leaves the surface.
  const Mesh s = test::icosphere(2);
  EXPECT_NEAR(surface_distance(s, s, options).hausdorff, 0.0, 1e-12);
}

TEST(SurfaceDistance, DensityGivesSamplesPerUnitArea) {
  const Mesh a = test::grid(4);  // area 16
  SurfaceDistanceOptions options;
  options.density = 50;  // 800 face samples
  options.vertex_errors = true;
  const SurfaceDistance d = surface_distance(a, a, options);
  EXPECT_NEAR(static_cast<double>(d.a_to_b.face_samples), 800.0, 40.0);
  EXPECT_EQ(d.face_error.size(), a.num_faces());
  EXPECT_EQ(d.vertex_error.size(), a.num_vertices());
}

TEST(BoundedHausdorff, BoundsContainTheAnalyticValue) {
  // Parallel 4x4 grids 0.25 apart: the Hausdorff distance is exactly 0.25.
  const Mesh a = test::grid(4);
  Mesh b = a;
  for (Vec3& p : b.positions) p.z += 0.25;
  const HausdorffBounds h = bounded_hausdorff(a, b, 1e-3, surface_distance(a, b).hausdorff);
  EXPECT_LE(h.lower, 0.25 + 1e-12);
  EXPECT_GE(h.upper, 0.25 - 1e-12);
  EXPECT_LE(h.upper - h.lower, 2e-3 + 1e-12);
  // A sphere moved by t: the bounds contain the sampled value and are at most 2 tol wide.
  const Mesh s = test::icosphere(3);
  Mesh moved = s;
  for (Vec3& p : moved.positions) p += Vec3{0.05, 0, 0};
  const double sampled = surface_distance(s, moved).hausdorff;
  const HausdorffBounds hs = bounded_hausdorff(s, moved, 1e-4, sampled);
  EXPECT_GE(hs.upper, sampled);
  EXPECT_LE(hs.upper, 0.05 + 1e-4 + 1e-9);  // nothing is farther than the translation
}

}  // namespace
}  // namespace visimp
