// VG weighting and many-levels runs of the collapse engine (simplify.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "test_meshes.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/io/mesh_io.h"
#include "visimp/simplify/simplify.h"

namespace visimp {
namespace {

SimplifyOptions vg_options(std::vector<float> visibility) {
  SimplifyOptions o;
  o.method = SimplifyMethod::vg;
  o.face_visibility = std::move(visibility);
  return o;
}

void expect_identical(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.num_faces(), b.num_faces());
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  EXPECT_TRUE(a.faces == b.faces);
  EXPECT_TRUE(a.positions == b.positions);  // Vec3 == is exact: bit for bit
}

// `seen` (V = 1) with `hidden` (V = 0) beside it, 3 units along +x.
struct SeenBesideHidden {
  Mesh mesh;
  std::vector<float> visibility;
};

SeenBesideHidden seen_beside_hidden(const Mesh& seen, const Mesh& hidden) {
  SeenBesideHidden out{seen, std::vector<float>(seen.num_faces() + hidden.num_faces(), 1.0f)};
  for (const Vec3& p : hidden.positions) out.mesh.positions.push_back(p + Vec3{3, 0, 0});
  const auto offset = static_cast<VertexIndex>(seen.num_vertices());
  for (const Face& f : hidden.faces) out.mesh.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  std::fill(out.visibility.begin() + static_cast<std::ptrdiff_t>(seen.num_faces()), out.visibility.end(), 0.0f);
  return out;
}

TEST(VisibilityGuided, WithVisibilityOneEverywhereItIsQbBitForBit) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  SimplifyOptions qb;
  qb.target_faces = 500;
  SimplifyOptions vg = vg_options(std::vector<float>(bunny.num_faces(), 1.0f));
  vg.target_faces = 500;
  expect_identical(simplify(bunny, qb).mesh, simplify(bunny, vg).mesh);
}

// Two spheres side by side, the right one "hidden" (V = 0): VG spends the collapses there
// while QB splits them by geometry.
TEST(VisibilityGuided, HiddenFacesAreCollapsedFirst) {
  const Mesh sphere = test::icosphere(3);
  const auto [pair, visibility] = seen_beside_hidden(sphere, sphere);

  auto faces_left = [](const Mesh& m) {
    return std::count_if(m.faces.begin(), m.faces.end(), [&](const Face& f) { return m.positions[f[0]].x < 1.5; });
  };
  SimplifyOptions qb;
  qb.target_faces = pair.num_faces() * 6 / 10;  // the hidden sphere alone can give that many
  SimplifyOptions vg = vg_options(visibility);
  vg.target_faces = qb.target_faces;
  const Mesh by_qb = simplify(pair, qb).mesh, by_vg = simplify(pair, vg).mesh;
  EXPECT_EQ(faces_left(by_vg), static_cast<std::ptrdiff_t>(sphere.num_faces()));  // the seen sphere untouched
  EXPECT_LT(faces_left(by_qb), static_cast<std::ptrdiff_t>(sphere.num_faces()) * 3 / 4);
  // Input V travels with the faces that survive.
  Mesh with_quality = pair;
  with_quality.face_quality = visibility;
  const Mesh kept = simplify(with_quality, vg).mesh;
  for (std::size_t f = 0; f < kept.num_faces(); ++f)
    EXPECT_EQ(kept.face_quality[f], kept.positions[kept.faces[f][0]].x < 1.5 ? 1.0f : 0.0f);
}

// A uniform V scales every cost by the same power of two here, so any exponent orders the
// queue exactly as QB does; a varying V makes the exponent matter.
TEST(VisibilityGuided, ExponentOnlyMattersWhereVisibilityVaries) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  SimplifyOptions qb;
  qb.target_faces = 700;
  const Mesh reference = simplify(bunny, qb).mesh;
  for (double exponent : {1.0, 2.0, 3.0}) {
    SimplifyOptions vg = vg_options(std::vector<float>(bunny.num_faces(), 0.5f));
    vg.target_faces = qb.target_faces;
    vg.visibility_exponent = exponent;
    SCOPED_TRACE("exponent " + std::to_string(exponent));
    expect_identical(reference, simplify(bunny, vg).mesh);
  }
  // Where V varies, the exponent is used: V and V² order the queue differently.
  std::vector<float> varying(bunny.num_faces());
  for (std::size_t f = 0; f < varying.size(); ++f) varying[f] = 0.2f + 0.8f * float(f % 7) / 6.0f;
  SimplifyOptions linear = vg_options(varying), squared = vg_options(varying);
  linear.target_faces = squared.target_faces = qb.target_faces;
  linear.visibility_exponent = 1.0;
  EXPECT_FALSE(simplify(bunny, linear).mesh.faces == simplify(bunny, squared).mesh.faces);
  SimplifyOptions bad = qb;
  for (double exponent : {0.0, -1.0, std::numeric_limits<double>::infinity()}) {
    bad.visibility_exponent = exponent;
    EXPECT_THROW(check_options(bad), UsageError);
  }
}

// Where no camera saw anything, Q_v = 0: the hidden part must still lose its least important
// detail first, as QB would on it alone (same largest collapse error), not in heap order.
TEST(VisibilityGuided, HiddenPartsAreCollapsedInOrderOfPlainError) {
  Mesh bumpy = test::icosphere(3);
  for (std::size_t v = 0; v < bumpy.num_vertices(); ++v)  // deterministic relief of ±5%
    bumpy.positions[v] = bumpy.positions[v] * (1.0 + 0.05 * std::sin(7.0 * double(v)));
  const Mesh visible = test::icosphere(2);
  const auto [pair, visibility] = seen_beside_hidden(visible, bumpy);

  const std::size_t hidden_target = bumpy.num_faces() / 2;
  SimplifyOptions alone;
  alone.target_faces = hidden_target;
  alone.boundary_weight = 0;
  SimplifyOptions vg = vg_options(visibility);
  vg.target_faces = visible.num_faces() + hidden_target;
  vg.boundary_weight = 0;
  const Simplified by_qb = simplify(bumpy, alone), by_vg = simplify(pair, vg);
  ASSERT_EQ(by_vg.mesh.num_faces(), by_qb.mesh.num_faces() + visible.num_faces());
  // Relative errors: the pair's diagonal is larger, so scale VG's back to the bumpy sphere's.
  const double scale = bounding_box(pair).diagonal() / bounding_box(bumpy).diagonal();
  EXPECT_LT(by_vg.result.max_error * scale, 1.5 * by_qb.result.max_error);
}

// --crease-visibility: a face across a crease (> 30°) from a more visible face takes that
// face's V, and nothing else changes. On a tessellated cube with a seen top and grazing sides,
// exactly the side faces along the top's rim are raised, each to the V of the top face across
// its edge: the run must equal a plain VG run given those raised values by hand.
TEST(VisibilityGuided, CreaseVisibilityRaisesTheFacesAlongAVisibleRim) {
  // A deterministic relief of ±0.5% (faces tilt < 10°) gives every collapse a cost: on a flat
  // cube all of them cost 0 and the weights could only reorder ties.
  const Mesh flat = test::subdivided_cube(8);
  Mesh cube = flat;
  for (std::size_t v = 0; v < cube.num_vertices(); ++v)
    cube.positions[v] = cube.positions[v] * (1.0 + 0.005 * std::sin(7.0 * double(v)));
  const double top = bounding_box(flat).max.z;
  auto normal_z = [&](const Face& f) {
    const Vec3 n = cross(flat.positions[f[1]] - flat.positions[f[0]], flat.positions[f[2]] - flat.positions[f[0]]);
    return n.z / norm(n);
  };
  // Top faces V = 1, every third 0.5 (flat neighbours: not a crease, nothing is raised there);
  // sides and bottom 0.1.
  std::vector<float> visibility(cube.num_faces());
  for (std::size_t f = 0; f < cube.num_faces(); ++f)
    visibility[f] = normal_z(cube.faces[f]) > 0.5 ? (f % 3 == 0 ? 0.5f : 1.0f) : 0.1f;
  std::vector<float> raised = visibility;
  std::size_t rim_faces = 0;
  for (std::size_t f = 0; f < cube.num_faces(); ++f) {
    const Face& face = cube.faces[f];
    if (std::abs(normal_z(face)) > 0.5) continue;
    for (int k = 0; k < 3; ++k) {  // a side face's edge on the top's rim: take the top face across it
      const VertexIndex a = face[k], b = face[(k + 1) % 3];
      if (flat.positions[a].z != top || flat.positions[b].z != top) continue;
      for (std::size_t g = 0; g < cube.num_faces(); ++g) {
        const Face& other = cube.faces[g];
        const bool shares =
            g != f && std::count(other.begin(), other.end(), a) && std::count(other.begin(), other.end(), b);
        if (shares) raised[f] = std::max(raised[f], visibility[g]);
      }
      ++rim_faces;
    }
  }
  ASSERT_GT(rim_faces, 0u);
  SimplifyOptions crease = vg_options(visibility), by_hand = vg_options(raised), plain = vg_options(visibility);
  crease.crease_visibility = true;
  crease.target_faces = by_hand.target_faces = plain.target_faces = cube.num_faces() / 4;
  const Mesh with_crease = simplify(cube, crease).mesh;
  expect_identical(with_crease, simplify(cube, by_hand).mesh);
  EXPECT_FALSE(with_crease.faces == simplify(cube, plain).mesh.faces);  // the option does something
}

TEST(VisibilityGuided, RejectsMissingOrOutOfRangeVisibility) {
  const Mesh m = test::icosphere(1);
  SimplifyOptions o = vg_options({});
  o.target_faces = 20;
  EXPECT_THROW(simplify(m, o), UsageError);
  o.face_visibility.assign(m.num_faces(), 0.5f);
  o.face_visibility[3] = 1.5f;
  EXPECT_THROW(simplify(m, o), UsageError);
  o.face_visibility[3] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(simplify(m, o), UsageError);
}

// Every level of one run equals a separate run to its count with serial_collapses (one
// collapse sequence, as the levels run): on a closed mesh at odd targets (the level ends one
// below, taking its deferred collapse in place), on an open one (boundary collapses can hit
// the target exactly; levels are finished on a copy), and with VG weights.
void expect_levels_equal_separate_runs(const Mesh& m, const SimplifyOptions& base,
                                       const std::vector<std::size_t>& targets) {
  const std::vector<Simplified> levels = simplify_levels(m, base, targets);
  ASSERT_EQ(levels.size(), targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    SimplifyOptions o = base;
    o.target_faces = targets[i];
    o.serial_collapses = true;
    const Simplified separate = simplify(m, o);
    SCOPED_TRACE("target " + std::to_string(targets[i]));
    expect_identical(levels[i].mesh, separate.mesh);
    EXPECT_EQ(levels[i].result.collapses, separate.result.collapses);
    EXPECT_EQ(levels[i].result.stop_reason, separate.result.stop_reason);
  }
}

TEST(SimplifyLevels, EachLevelEqualsASeparateRun) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  expect_levels_equal_separate_runs(bunny, SimplifyOptions{}, {2001, 1501, 1000, 333, 101, 1000});
  const Mesh open = read_mesh(test::bundled_mesh("aneurysm_open.ply"));
  expect_levels_equal_separate_runs(open, SimplifyOptions{}, {open.num_faces() / 2 + 1, open.num_faces() / 5 + 1, 301});
  std::vector<float> v(bunny.num_faces());
  for (std::size_t f = 0; f < v.size(); ++f) v[f] = float(f % 7) / 6.0f;
  expect_levels_equal_separate_runs(bunny, vg_options(v), {1801, 700, 99});
}

// A bumpy sphere of 163,842 vertices: three partitions of the parallel phase, costs that
// differ from place to place (a plain icosphere ties nearly everything).
Mesh bumpy_sphere() {
  Mesh m = test::icosphere(7);
  for (Vec3& p : m.positions) p = p * (1.0 + 0.05 * std::sin(9 * p.x) * std::sin(7 * p.y + 1) * std::sin(5 * p.z + 2));
  return m;
}

// Runs `o` with 2 and 3 threads: the same mesh, phase and error as `one`, its 1-thread run.
void expect_same_with_more_threads(const Mesh& m, SimplifyOptions o, const Simplified& one) {
  for (unsigned threads : {2u, 3u}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    o.threads = threads;
    const Simplified many = simplify(m, o);
    expect_identical(one.mesh, many.mesh);
    EXPECT_EQ(one.result.parallel_collapses, many.result.parallel_collapses);
    EXPECT_EQ(one.result.max_error, many.result.max_error);
  }
}

TEST(SimplifyParallel, TheMeshIsTheSameForEveryThreadCount) {
  const Mesh m = bumpy_sphere();
  for (SimplifyMethod method : {SimplifyMethod::qb, SimplifyMethod::vg}) {
    SimplifyOptions o;
    o.method = method;
    if (method == SimplifyMethod::vg)
      for (std::size_t f = 0; f < m.num_faces(); ++f)
        o.face_visibility.push_back(m.positions[m.faces[f][0]].z > 0.3 ? 1.0f : 0.2f);
    for (double ratio : {0.2, 0.1, 0.02}) {  // the phase's three rungs
      SCOPED_TRACE("ratio " + std::to_string(ratio));
      o.target_ratio = ratio;
      o.threads = 1;
      const Simplified one = simplify(m, o);
      // The phase ran and did most of the work, and left the rest to the serial loop.
      EXPECT_GT(one.result.parallel_collapses, one.result.collapses / 2);
      EXPECT_LT(one.result.parallel_collapses, one.result.collapses);
      EXPECT_EQ(one.result.stop_reason, StopReason::target_reached);
      expect_same_with_more_threads(m, o, one);
    }
  }
}

TEST(SimplifyParallel, AnOpenMeshIsTheSameForEveryThreadCount) {
  // Holes all over the bumpy sphere: its 160k vertices span ten of the set-up's parallel
  // ranges (in the engine's spatial order), each with boundary edges, whose planes must all reach the quadrics, in vertex
  // order, whichever thread classified their range (a range's planes left out fails this).
  const Mesh closed = bumpy_sphere();
  Mesh m;
  m.positions = closed.positions;
  for (const Face& f : closed.faces) {
    const Vec3 c = (closed.positions[f[0]] + closed.positions[f[1]] + closed.positions[f[2]]) / 3.0;
    if (std::sin(13 * c.x) * std::sin(11 * c.y) * std::sin(7 * c.z) < 0.5) m.faces.push_back(f);
  }
  ASSERT_GT(analyze(m).boundary_edges, 1000u);
  SimplifyOptions o;
  o.target_ratio = 0.1;
  o.threads = 1;
  const Simplified one = simplify(m, o);
  EXPECT_EQ(one.result.stop_reason, StopReason::target_reached);
  expect_same_with_more_threads(m, o, one);
}

TEST(SimplifyParallel, LevelsAreOneSerialSequenceWhereSingleTargetsUseThePhase) {
  // 50% is above the phase's first rung (3/10 of the input); simplify() runs 30% and 20% under
  // the first rung's phase, 10% under the second's (12% and below), 9001 faces (2.7%) and 3000
  // under the deepest one (5% and below). Levels run none of them: one sequence for all.
  const Mesh m = bumpy_sphere();
  const std::vector<std::size_t> targets{m.num_faces() / 2, m.num_faces() * 3 / 10, m.num_faces() / 5,
                                         m.num_faces() / 10, 9001, 3000};
  expect_levels_equal_separate_runs(m, SimplifyOptions{}, targets);
  const std::vector<Simplified> levels = simplify_levels(m, SimplifyOptions{}, targets);
  for (const Simplified& level : levels) {
    EXPECT_EQ(level.result.parallel_collapses, 0u);
    EXPECT_EQ(level.result.stage_seconds.parallel_phase, 0.0);
  }
  SimplifyOptions phased;
  phased.target_faces = 9001;
  const Simplified with_phase = simplify(m, phased);
  EXPECT_GT(with_phase.result.parallel_collapses, 0u);
  EXPECT_NE(with_phase.mesh.faces, levels[4].mesh.faces);  // the phase's own sequence: another mesh
  SimplifyOptions o;
  o.target_faces = m.num_faces() / 2;
  const SimplifyResult serial = simplify(m, o).result;
  EXPECT_EQ(serial.parallel_collapses, 0u);
  EXPECT_EQ(serial.stage_seconds.parallel_phase, 0.0);
  o.target_faces = m.num_faces() / 5;
  const SimplifyResult first_rung = simplify(m, o).result;
  o.target_faces = m.num_faces() / 10;
  const SimplifyResult second_rung = simplify(m, o).result;
  o.target_faces = 9001;
  const SimplifyResult parallel = simplify(m, o).result;
  EXPECT_GT(first_rung.parallel_collapses, 0u);
  // Each deeper rung does more of the work in the phase: partitions go on to 88% and to 95%
  // removed, where the first rung stops rounds at 35% of the faces left.
  EXPECT_GT(second_rung.parallel_collapses, first_rung.parallel_collapses + m.num_faces() / 20);
  EXPECT_GT(parallel.parallel_collapses, second_rung.parallel_collapses + m.num_faces() / 40);
  // ...without crushing the partitions' interiors: largest collapse error 1.50e-4 of the
  // diagonal (measured); 3.54e-4 when rung 3's goal counted the full-resolution cut band too.
  EXPECT_LT(parallel.max_error, 2.0e-4);
  // The stages account for the run: each took time, and together no more than the whole.
  for (const SimplifyResult& r : {serial, parallel}) {
    const SimplifyStageSeconds& s = r.stage_seconds;
    EXPECT_GT(s.setup, 0.0);
    EXPECT_GT(s.serial, 0.0);
    EXPECT_GT(s.extract, 0.0);
    EXPECT_LE(s.setup + s.parallel_phase + s.serial + s.extract, r.seconds);
  }
  EXPECT_GT(parallel.stage_seconds.parallel_phase, 0.0);
}

TEST(SimplifyLevels, TargetsAboveTheInputKeepIt) {
  const Mesh m = test::icosphere(1);
  const std::vector<Simplified> levels = simplify_levels(m, SimplifyOptions{}, {1000, 40});
  EXPECT_EQ(levels[0].mesh.num_faces(), m.num_faces());
  EXPECT_LE(levels[1].mesh.num_faces(), 40u);
  EXPECT_THROW(simplify_levels(m, SimplifyOptions{}, {}), UsageError);
  EXPECT_THROW(simplify_levels(m, SimplifyOptions{}, {0}), UsageError);
}

}  // namespace
}  // namespace visimp
