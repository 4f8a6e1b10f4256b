#include "visimp/simplify/simplify.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "test_meshes.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/validate.h"
#include "visimp/io/mesh_io.h"
#include "visimp/metrics/surface_distance.h"
#include "visimp/visibility/visibility.h"

namespace visimp {
namespace {

std::size_t fold_edges(const Mesh& m);  // below, with the real-mesh invariants

Simplified simplify_to(const Mesh& m, std::size_t target) {
  SimplifyOptions o;
  o.target_faces = target;
  return simplify(m, o);
}

void expect_all_finite(const Mesh& m) {
  for (const Vec3& p : m.positions) ASSERT_TRUE(is_finite(p));
}

TEST(Simplify, FlatGridBecomesTwoTrianglesWithZeroError) {
  const Mesh g = test::grid(8);  // 128 faces
  const Simplified s = simplify_to(g, 2);
  EXPECT_EQ(s.mesh.num_faces(), 2u);
  EXPECT_EQ(s.result.stop_reason, StopReason::target_reached);
  EXPECT_EQ(s.result.max_error, 0.0);
  // The survivors are the four corners, exactly.
  std::set<std::pair<double, double>> corners;
  for (const Face& f : s.mesh.faces)
    for (VertexIndex v : f) corners.insert({s.mesh.positions[v].x, s.mesh.positions[v].y});
  EXPECT_EQ(corners, (std::set<std::pair<double, double>>{{0, 0}, {8, 0}, {0, 8}, {8, 8}}));
  EXPECT_NEAR(analyze(s.mesh).area, 64.0, 1e-12);
}

TEST(Simplify, CubeKeepsItsEightCornersExactly) {
  const Mesh cube = test::subdivided_cube(4);  // 192 faces
  const Simplified s = simplify_to(cube, 12);
  EXPECT_EQ(s.mesh.num_faces(), 12u);
  EXPECT_EQ(s.mesh.num_vertices(), 8u);
  for (const Vec3& p : s.mesh.positions)
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(p[k] == 0.0 || p[k] == 1.0) << p.x << " " << p.y << " " << p.z;
  EXPECT_TRUE(analyze(s.mesh).closed_manifold());
  EXPECT_NEAR(analyze(s.mesh).area, 6.0, 1e-12);
}

// Largest distance of a boundary-ish vertex (|z| tiny) from the square outline of a bumped grid.
double outline_deviation(const Mesh& m, double size) {
  double worst = 0;
  for (const Vec3& p : m.positions) {
    if (std::abs(p.z) > 1e-3) continue;  // interior of the bump
    const double d = std::min({std::abs(p.x), std::abs(p.x - size), std::abs(p.y), std::abs(p.y - size)});
    worst = std::max(worst, d);
  }
  return worst;
}

TEST(Simplify, OpenGridKeepsItsBoundaryOutline) {
  // A grid bent into a gentle bump (z = 0 on the outline) keeps its square outline: boundary
  // planes hold the outline's vertices on it (up to the compromise with the face planes) and
  // its corners in place.
  Mesh g = test::grid(10);
  for (Vec3& p : g.positions) p.z = 0.3 * std::sin(p.x / 10 * M_PI) * std::sin(p.y / 10 * M_PI);
  const Simplified s = simplify_to(g, 40);
  EXPECT_LE(s.mesh.num_faces(), 40u);
  EXPECT_LT(outline_deviation(s.mesh, 10), 1e-3);  // 1e-4 of the size
  const BoundingBox box = analyze(s.mesh).bbox;
  EXPECT_NEAR(box.min.x, 0, 1e-3);
  EXPECT_NEAR(box.max.x, 10, 1e-3);
  EXPECT_NEAR(box.min.y, 0, 1e-3);
  EXPECT_NEAR(box.max.y, 10, 1e-3);
  // Without boundary planes the same run lets the outline wander: the check above can fail.
  SimplifyOptions loose;
  loose.target_faces = 40;
  loose.boundary_weight = 0;
  const Simplified l = simplify(g, loose);
  const BoundingBox lb = analyze(l.mesh).bbox;
  EXPECT_GT(std::max({outline_deviation(l.mesh, 10), std::abs(lb.min.x), std::abs(lb.max.x - 10), std::abs(lb.min.y),
                      std::abs(lb.max.y - 10)}),
            1e-2);
}

TEST(Simplify, FrozenBoundaryNeverMoves) {
  Mesh g = test::grid(6);
  for (Vec3& p : g.positions) p.z = 0.1 * p.x * p.y;
  SimplifyOptions o;
  o.target_ratio = 0.1;
  o.freeze_boundary = true;
  const Simplified s = simplify(g, o);
  std::size_t outline = 0;
  for (const Vec3& p : s.mesh.positions) outline += (p.x == 0 || p.x == 6 || p.y == 0 || p.y == 6);
  EXPECT_EQ(outline, 24u);  // all 24 outline vertices of the 7×7 lattice
  EXPECT_EQ(s.result.stop_reason, StopReason::no_legal_collapse);
}

TEST(Simplify, FrozenBoundaryTakesInEveryInteriorVertex) {
  // A flat 6×6 grid (72 faces) with its outline frozen: the 25 interior vertices can only
  // disappear by collapsing onto the outline (a free vertex merges into a locked one, which
  // stays put). Flat, so every such collapse costs 0 and the end is the outline alone: 24
  // vertices triangulated by 24 − 2 = 22 faces, the square's area exactly, error 0. When
  // locked vertices took in nothing, interior vertices whose every neighbour was on the
  // outline were stuck.
  SimplifyOptions o;
  o.target_faces = 1;
  o.freeze_boundary = true;
  const Simplified s = simplify(test::grid(6), o);
  EXPECT_EQ(s.mesh.num_vertices(), 24u);
  EXPECT_EQ(s.mesh.num_faces(), 22u);
  EXPECT_LE(s.result.max_error, 1e-7);  // 0 up to the rounding of the expanded quadric form
  EXPECT_NEAR(analyze(s.mesh).area, 36.0, 1e-12);
  for (const Vec3& p : s.mesh.positions) EXPECT_TRUE(p.x == 0 || p.x == 6 || p.y == 0 || p.y == 6);
  EXPECT_TRUE(validate(s.mesh).ok());
}

TEST(Simplify, HalfEdgeCollapseNeverMisorientsANonManifoldEdge) {
  // Regression (fuzz_simplify): a free vertex merging into a locked one took a face off a
  // 3-face edge, and the two faces left ran the same way (non-manifold edge → misoriented).
  //
  //          c            faces (a, b, c) twice: edge ab has 3 faces (non-manifold), bc and
  //         / \           ca are misoriented, so a, b, c are locked; e is free (one face,
  //        a---b          two boundary edges) and could only merge into a or b, removing
  //         \ /           (b, a, e), the one face running b → a.
  //          e
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}};
  m.faces = {{0, 1, 2}, {0, 1, 2}, {1, 0, 3}};
  const MeshStats before = analyze(m);
  ASSERT_EQ(before.non_manifold_edges, 1u);
  ASSERT_EQ(before.misoriented_edges, 2u);
  const Simplified s = simplify_to(m, 1);
  const MeshStats after = analyze(s.mesh);
  EXPECT_LE(after.misoriented_edges, before.misoriented_edges);
  EXPECT_LE(after.non_manifold_vertices, before.non_manifold_vertices);
  EXPECT_EQ(s.mesh.num_faces(), 3u);  // nothing may go: every collapse would break the fan
  EXPECT_EQ(s.result.stop_reason, StopReason::no_legal_collapse);
}

TEST(Simplify, NoFoldsRemovesTheFoldsOfARealCadPartAtTheSameError) {
  // kicad_esp_wroom02 at 10%: its thin layers fold at 41 edges with plain QB; with
  // prevent_folds none, and the Hausdorff distance stays within 2% (measured: equal).
  const Mesh esp = read_mesh(test::bundled_mesh("kicad_esp_wroom02.ply"));
  SimplifyOptions o;
  o.target_ratio = 0.1;
  const Simplified plain = simplify(esp, o);
  o.prevent_folds = true;
  const Simplified kept = simplify(esp, o);
  EXPECT_GT(fold_edges(plain.mesh), 10u);
  EXPECT_EQ(fold_edges(kept.mesh), 0u);
  EXPECT_EQ(kept.mesh.num_faces(), plain.mesh.num_faces());
  SurfaceDistanceOptions d;
  d.samples = 200000;
  const double h_plain = surface_distance(esp, plain.mesh, d).hausdorff;
  const double h_kept = surface_distance(esp, kept.mesh, d).hausdorff;
  EXPECT_LT(h_kept, 1.02 * h_plain);
}

TEST(Simplify, ClosedMeshWithOddTargetEndsOneBelow) {
  const Mesh sphere = test::icosphere(2);  // 320 faces; a closed mesh loses 2 per collapse
  const Simplified s = simplify_to(sphere, 101);
  EXPECT_EQ(s.mesh.num_faces(), 100u);
  EXPECT_EQ(s.result.stop_reason, StopReason::target_reached);
}

// An open mesh can reach a target of the other parity: one collapse of a boundary edge
// removes one face. The loop must keep looking for it past the first deferred collapse.
TEST(Simplify, OpenMeshWithTargetOfTheOtherParityHitsItExactly) {
  const Mesh sphere = test::icosphere(3);
  Mesh capless;
  capless.positions = sphere.positions;
  for (const Face& f : sphere.faces)
    if (sphere.positions[f[0]].z + sphere.positions[f[1]].z + sphere.positions[f[2]].z < 3 * 0.7)
      capless.faces.push_back(f);
  ASSERT_FALSE(analyze(capless).closed_manifold());
  std::size_t target = capless.num_faces() / 3;
  if ((capless.num_faces() - target) % 2 == 0) ++target;  // interior collapses alone cannot hit it
  const Simplified s = simplify_to(capless, target);
  EXPECT_EQ(s.mesh.num_faces(), target);
  EXPECT_EQ(s.result.stop_reason, StopReason::target_reached);
}

TEST(Simplify, StopsAtTheErrorLimit) {
  const Mesh sphere = test::icosphere(3);
  SimplifyOptions o;
  o.max_error = 1e-3;
  const Simplified s = simplify(sphere, o);
  EXPECT_EQ(s.result.stop_reason, StopReason::error_limit);
  EXPECT_LE(s.result.max_error, 1e-3);
  EXPECT_LT(s.mesh.num_faces(), sphere.num_faces());
  EXPECT_GT(s.mesh.num_faces(), 20u);
}

TEST(Simplify, TetrahedronCannotCollapseFurther) {
  const Mesh sphere = test::icosphere(1);
  const Simplified s = simplify_to(sphere, 1);
  EXPECT_EQ(s.mesh.num_faces(), 4u);
  EXPECT_EQ(s.result.stop_reason, StopReason::no_legal_collapse);
  EXPECT_TRUE(analyze(s.mesh).closed_manifold());
}

TEST(Simplify, RejectsBadOptions) {
  const Mesh g = test::grid(2);
  SimplifyOptions o;
  EXPECT_THROW(simplify(g, o), UsageError);  // no target and no error limit
  o.target_ratio = 1.5;
  EXPECT_THROW(simplify(g, o), UsageError);
  o.target_ratio = 0.5;
  o.max_normal_change_deg = 0;
  EXPECT_THROW(simplify(g, o), UsageError);
}

// Area weights (the default) keep large flat faces where they are; uniform weights (CGAL GH's)
// keep densely tessellated detail. Measured at 10% (docs/simplify.md): the ESP module's RMS
// distance is ~7x lower with area weights, the teapot's Hausdorff distance (dense spout and
// lid) ~27% lower with uniform ones. Fails if the option is ignored either way.
TEST(Simplify, QuadricWeightsTradeRmsOnFlatFacesForHausdorffOnDenseDetail) {
  SurfaceDistanceOptions d;
  d.samples = 200000;
  auto distance = [&](const Mesh& m, QuadricWeights weights) {
    SimplifyOptions o;
    o.target_ratio = 0.1;
    o.quadric_weights = weights;
    return surface_distance(m, simplify(m, o).mesh, d);
  };
  const Mesh esp = read_mesh(test::bundled_mesh("kicad_esp_wroom02.ply"));
  EXPECT_LT(distance(esp, QuadricWeights::area).rms, distance(esp, QuadricWeights::uniform).rms / 3);
  const Mesh teapot = read_mesh(test::bundled_mesh("teapot.ply"));
  EXPECT_LT(distance(teapot, QuadricWeights::uniform).hausdorff,
            0.85 * distance(teapot, QuadricWeights::area).hausdorff);
}

// A floor of one median face area under the area weights (--area-floor 1): the small faces of
// the teapot's spout and lid are no longer nearly free to remove, so its Hausdorff distance at
// 10% drops (measured 9.4e-3 -> 5.4e-3 of the diagonal; uniform weights 6.8e-3), while the ESP
// module's large flat faces still outweigh its small ones (RMS 6.8e-5 -> 7.5e-5; uniform
// 4.8e-4). Fails if the floor is ignored, or if it is so large that the weights become uniform.
TEST(Simplify, AreaFloorKeepsSmallDetailAndStillHoldsLargeFlatFaces) {
  SurfaceDistanceOptions d;
  d.samples = 200000;
  auto distance = [&](const Mesh& m, QuadricWeights weights, double floor) {
    SimplifyOptions o;
    o.target_ratio = 0.1;
    o.quadric_weights = weights;
    o.area_floor = floor;
    return surface_distance(m, simplify(m, o).mesh, d);
  };
  const Mesh teapot = read_mesh(test::bundled_mesh("teapot.ply"));
  EXPECT_LT(distance(teapot, QuadricWeights::area, 1.0).hausdorff,
            0.7 * distance(teapot, QuadricWeights::area, 0.0).hausdorff);
  const Mesh esp = read_mesh(test::bundled_mesh("kicad_esp_wroom02.ply"));
  const double floor_rms = distance(esp, QuadricWeights::area, 1.0).rms;
  EXPECT_LT(floor_rms, distance(esp, QuadricWeights::uniform, 0.0).rms / 3);
  EXPECT_LT(floor_rms, 1.25 * distance(esp, QuadricWeights::area, 0.0).rms);
}

TEST(Simplify, AreaFloorIsForAreaWeightsAndFiniteOnly) {
  const Mesh g = test::grid(4);
  SimplifyOptions o;
  o.target_ratio = 0.5;
  o.area_floor = -1;
  EXPECT_THROW(simplify(g, o), OptionError);
  o.area_floor = std::numeric_limits<double>::infinity();
  EXPECT_THROW(simplify(g, o), OptionError);
  o.area_floor = 1;
  o.quadric_weights = QuadricWeights::uniform;
  try {
    check_options(o);
    ADD_FAILURE() << "a floor under uniform weights was taken";
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), &o.area_floor);
    EXPECT_NE(std::string(e.what()).find("area weights only"), std::string::npos) << e.what();
  }
  o.quadric_weights = QuadricWeights::area;
  EXPECT_NO_THROW(simplify(g, o));
}

TEST(Simplify, QuadricWeightsFlagTakesOnlyItsNames) {
  SimplifyOptions o;
  std::vector<OptionSpec> specs = describe_options(o);
  const auto spec =
      std::find_if(specs.begin(), specs.end(), [](const OptionSpec& s) { return s.flag == "--quadric-weights"; });
  ASSERT_NE(spec, specs.end());
  EXPECT_EQ(spec->default_text, "area");
  EXPECT_NE(spec->help.find("area"), std::string::npos);
  EXPECT_NE(spec->help.find("uniform"), std::string::npos);
  spec->set("uniform");
  EXPECT_EQ(o.quadric_weights, QuadricWeights::uniform);
  spec->set("area");
  EXPECT_EQ(o.quadric_weights, QuadricWeights::area);
  try {
    spec->set("Area");
    ADD_FAILURE() << "'Area' was taken";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "--quadric-weights must be one of area|uniform, not 'Area'");
  }
  EXPECT_THROW(spec->set(""), UsageError);
  EXPECT_EQ(o.quadric_weights, QuadricWeights::area);  // a refused value changes nothing
}

// The bunny far from the origin and at a tiny scale must simplify to the same shape: same
// relative error within 1% as at the origin (DESIGN.md numerical rules).
TEST(Simplify, OffsetAndScaleDoNotChangeTheRelativeError) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  Mesh moved = bunny;
  for (Vec3& p : moved.positions) p = (p + Vec3{1e7, -1e7, 1e7}) * 1e-6;
  SimplifyOptions o;
  o.target_ratio = 0.1;
  const Simplified a = simplify(bunny, o), b = simplify(moved, o);
  EXPECT_EQ(a.mesh.num_faces(), b.mesh.num_faces());
  SurfaceDistanceOptions d;
  d.samples = 100000;
  const SurfaceDistance da = surface_distance(bunny, a.mesh, d), db = surface_distance(moved, b.mesh, d);
  EXPECT_NEAR(db.rms / db.diagonal, da.rms / da.diagonal, 0.01 * da.rms / da.diagonal);
  EXPECT_NEAR(db.hausdorff / db.diagonal, da.hausdorff / da.diagonal, 0.01 * da.hausdorff / da.diagonal);
  EXPECT_NEAR(b.result.max_error, a.result.max_error, 0.01 * a.result.max_error);
}

// The lazy queue (docs/simplify.md, "Lazy re-costing"): a collapse costs only the edges it
// makes (and, after a free collapse, all at the merged vertex); an edge it changed is costed
// again when its entry reaches the front. Eagerly every edge at the merged vertex was costed
// at every collapse: 6.8 per collapse on the bunny at 10%, against 4.3. And no edge may be
// lost on the way: the bunny still goes down to 20 faces.
TEST(Simplify, LazyQueueCostsAChangedEdgeWhenItIsDueAndLosesNone) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  SimplifyOptions o;
  o.target_ratio = 0.1;
  const Simplified s = simplify(bunny, o);
  EXPECT_EQ(s.result.stop_reason, StopReason::target_reached);
  EXPECT_GT(s.result.requeued_edges, s.result.collapses);  // counted at all
  EXPECT_LT(s.result.requeued_edges, 5 * s.result.collapses);
  for (std::size_t target : {200u, 20u}) {
    const Simplified low = simplify_to(bunny, target);
    EXPECT_EQ(low.mesh.num_faces(), target);
    EXPECT_EQ(low.result.stop_reason, StopReason::target_reached);
  }
}

TEST(Simplify, SliversAndZeroAreaFacesGiveFiniteOutput) {
  // A grid whose middle column is squashed to 1e-9 wide (slivers), plus collinear and
  // coincident-vertex faces glued on.
  Mesh g = test::grid(6);
  for (Vec3& p : g.positions)
    if (p.x == 3) p.x = 2 + 1e-9;
  const VertexIndex base = VertexIndex(g.positions.size());
  g.positions.push_back({0, -1, 0});
  g.positions.push_back({0, -1, 0});       // coincident with the previous one
  g.faces.push_back({0, 1, base});         // a proper face below the grid
  g.faces.push_back({base, 1, base + 1});  // zero area: two coincident corners
  const Simplified s = simplify_to(g, 10);
  expect_all_finite(s.mesh);
  EXPECT_TRUE(validate(s.mesh).ok());
  EXPECT_LE(s.mesh.num_faces(), 10u);
}

TEST(Simplify, HundredThousandZeroAreaFacesAreHarmless) {
  // All faces collinear: no face has a plane, every collapse costs 0, nothing divides by zero.
  Mesh m;
  for (int i = 0; i < 50002; ++i) m.positions.push_back({double(i), 0, 0});
  for (VertexIndex i = 0; i + 2 < 50002; i += 1) m.faces.push_back({i, i + 1, i + 2});
  for (VertexIndex i = 0; i + 2 < 50002; i += 1) m.faces.push_back({i, i + 2, i + 1});
  ASSERT_EQ(m.num_faces(), 100000u);
  const Simplified s = simplify_to(m, 1000);
  expect_all_finite(s.mesh);
  EXPECT_TRUE(validate(s.mesh).ok());
}

TEST(Simplify, DuplicateFacesAndAFourFaceEdgeAreKeptLocked) {
  // A closed sphere with one face duplicated and a "fin" of two extra faces on one edge (4
  // faces there): those vertices are locked and the rest simplifies around them.
  Mesh m = test::icosphere(3);
  const Face dup = m.faces[0];
  m.faces.push_back(dup);
  const Face f1 = m.faces[100];
  const VertexIndex tip = VertexIndex(m.positions.size());
  m.positions.push_back(m.positions[f1[0]] * 1.5);
  m.faces.push_back({f1[0], f1[1], tip});
  m.faces.push_back({f1[1], f1[0], tip});
  const MeshStats before = analyze(m);
  ASSERT_GE(before.non_manifold_edges, 1u);
  const Simplified s = simplify_to(m, 200);
  EXPECT_GT(s.result.locked_vertices, 0u);
  EXPECT_LE(s.mesh.num_faces(), 201u);
  const MeshStats after = analyze(s.mesh);
  EXPECT_LE(after.non_manifold_edges, before.non_manifold_edges);
  EXPECT_EQ(after.duplicate_faces, before.duplicate_faces);  // duplicates stay, untouched
  for (const Vec3& p : {m.positions[dup[0]], m.positions[dup[1]], m.positions[dup[2]], m.positions[tip]})
    EXPECT_NE(std::find(s.mesh.positions.begin(), s.mesh.positions.end(), p), s.mesh.positions.end());
}

// A closed cone: apex, a ring of n vertices, a top vertex over the ring; consistently
// oriented, so every vertex but a shared apex is one closed fan.
void add_closed_cone(Mesh& m, VertexIndex apex, int n, double z) {
  const VertexIndex ring = VertexIndex(m.positions.size()), top = ring + VertexIndex(n);
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    m.positions.push_back({std::cos(a), std::sin(a), z});
  }
  m.positions.push_back({0, 0, 2 * z});
  for (int i = 0; i < n; ++i) {
    const VertexIndex r = ring + VertexIndex(i), r_next = ring + VertexIndex((i + 1) % n);
    m.faces.push_back(z > 0 ? Face{apex, r, r_next} : Face{apex, r_next, r});
    m.faces.push_back(z > 0 ? Face{top, r_next, r} : Face{top, r, r_next});
  }
}

// classify's shortcut for a vertex that is one closed fan (is_closed_fan, up to 16 faces) and
// its general test must agree: two cones meeting at their apex lock the apex (two fans), with
// the apex's 10 faces (the shortcut's range) and 18 (beyond it); a lone cone of 20 locks nothing.
TEST(Simplify, AnApexWhereTwoClosedConesMeetIsLockedAndNothingElse) {
  for (int n : {5, 9}) {
    Mesh m;
    m.positions.push_back({0, 0, 0});
    add_closed_cone(m, 0, n, 1.0);
    add_closed_cone(m, 0, n, -1.0);
    ASSERT_EQ(analyze(m).non_manifold_vertices, 1u) << n;
    const Simplified s = simplify_to(m, m.num_faces() - 4);
    EXPECT_EQ(s.result.locked_vertices, 1u) << "cones of " << n;
    EXPECT_EQ(analyze(s.mesh).non_manifold_edges, 0u);
  }
  Mesh lone;
  lone.positions.push_back({0, 0, 0});
  add_closed_cone(lone, 0, 20, 1.0);
  ASSERT_TRUE(validate(lone).ok());
  EXPECT_EQ(simplify_to(lone, lone.num_faces() - 4).result.locked_vertices, 0u);
}

// ---- invariants over every real mesh ---------------------------------------------------

using Kernel = CGAL::Simple_cartesian<double>;
using Triangle = Kernel::Triangle_3;
using Tree =
    CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::iterator>>>;

// Fraction of output faces whose normal points against the input surface's normal at the
// closest point: a flipped (folded-over) face shows up here.
double flipped_fraction(const Mesh& input, const Mesh& output) {
  std::vector<Triangle> triangles;
  std::vector<Vec3> normals;
  for (const Face& f : input.faces) {
    if (is_degenerate(input, f)) continue;
    auto pt = [&](VertexIndex v) {
      return Kernel::Point_3(input.positions[v].x, input.positions[v].y, input.positions[v].z);
    };
    triangles.emplace_back(pt(f[0]), pt(f[1]), pt(f[2]));
    normals.push_back(face_normal_unnormalized(input, f));
  }
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  std::size_t flipped = 0, counted = 0;
  for (const Face& f : output.faces) {
    if (is_degenerate(output, f)) continue;
    const Vec3 c = (output.positions[f[0]] + output.positions[f[1]] + output.positions[f[2]]) / 3.0;
    const auto hit = tree.closest_point_and_primitive(Kernel::Point_3(c.x, c.y, c.z));
    const Vec3 n_in = normals[std::size_t(hit.second - triangles.begin())];
    const Vec3 n_out = face_normal_unnormalized(output, f);
    ++counted;
    flipped += dot(n_in, n_out) < -0.5 * norm(n_in) * norm(n_out);
  }
  return counted ? double(flipped) / double(counted) : 0.0;
}

// Manifold edges whose two faces fold back onto each other (normals more than ~154° apart).
std::size_t fold_edges(const Mesh& m) {
  std::map<std::pair<VertexIndex, VertexIndex>, std::vector<std::size_t>> edge_faces;
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) edge_faces[std::minmax(m.faces[f][k], m.faces[f][(k + 1) % 3])].push_back(f);
  std::size_t folds = 0;
  for (const auto& [edge, faces] : edge_faces) {
    if (faces.size() != 2) continue;
    const Vec3 a = face_normal_unnormalized(m, m.faces[faces[0]]), b = face_normal_unnormalized(m, m.faces[faces[1]]);
    folds += dot(a, b) < -0.9 * norm(a) * norm(b);
  }
  return folds;
}

// Meshes that are one layer of surface (no thin plates or enclosed parts), where the closest
// input point to an output face lies on the same side.
bool single_layer(const std::string& path) {
  for (const char* name : {"bunny", "fandisk", "teapot", "aneurysm"})
    if (path.find(name) != std::string::npos) return true;
  return false;
}

class RealMeshInvariants : public ::testing::TestWithParam<std::string> {};

// Everything simplify() promises for one run on a real mesh.
void expect_every_promise(const std::string& path, const Mesh& input, const MeshStats& before, const SimplifyOptions& o,
                          bool check_folds = true) {
  const Simplified s = simplify(input, o);
  expect_all_finite(s.mesh);
  EXPECT_TRUE(validate(s.mesh).ok());
  const std::size_t target = s.result.target_faces;
  if (s.result.stop_reason == StopReason::target_reached) {
    EXPECT_LE(s.mesh.num_faces(), target);
    EXPECT_GE(s.mesh.num_faces() + 1, target);
  } else {
    // Only locked (non-manifold) parts may stop a run early, and then it says so.
    EXPECT_GT(before.non_manifold_edges + before.non_manifold_vertices, 0u) << to_string(s.result.stop_reason);
    EXPECT_EQ(s.result.stop_reason, StopReason::no_legal_collapse);
  }
  const MeshStats after = analyze(s.mesh);
  EXPECT_LE(after.non_manifold_edges, before.non_manifold_edges);
  EXPECT_LE(after.non_manifold_vertices, before.non_manifold_vertices);
  EXPECT_LE(after.misoriented_edges, before.misoriented_edges);
  EXPECT_LE(after.boundary_edges, before.boundary_edges);
  EXPECT_TRUE(std::isfinite(s.result.max_error));
  // A closed 2-manifold input stays closed and manifold.
  if (before.closed_manifold()) {
    EXPECT_TRUE(after.closed_manifold());
  }
  // No flipped faces on single-layer surfaces: at most 0.5% of faces point against the
  // input near them, and no edge folds back onto itself. (Thin CAD plates are flattened
  // into back-to-back sheets at high ratios: known, see docs/simplify.md.)
  if (single_layer(path)) {
    EXPECT_LE(flipped_fraction(input, s.mesh), 0.005);
    if (check_folds) {
      EXPECT_EQ(fold_edges(s.mesh), 0u);
    }
  }
}

TEST_P(RealMeshInvariants, SimplifyKeepsEveryPromise) {
  if (!std::filesystem::exists(GetParam())) GTEST_SKIP() << GetParam() << " is absent (../shared/meshes)";
  const Mesh input = read_mesh(GetParam());
  const Mesh copy = input;
  const MeshStats before = analyze(input);
  for (double ratio : {0.5, 0.1}) {
    SCOPED_TRACE(ratio);
    SimplifyOptions o;
    o.target_ratio = ratio;
    expect_every_promise(GetParam(), input, before, o);
  }
  // VG with the mesh's own V: hidden parts are collapsed first and hardest (thinned pins,
  // crushed interiors), a sequence QB never runs. Every promise holds but one: a hidden
  // interior crushed at no cost may fold onto itself (the teapot's spout, 3 edges at 10%;
  // docs/simplify.md, Known limits), so folds are not counted here.
  SCOPED_TRACE("vg");
  SimplifyOptions vg;
  vg.target_ratio = 0.1;
  vg.method = SimplifyMethod::vg;
  const auto renderer = make_raster_renderer({160, 2});
  vg.face_visibility = compute_visibility(input, octahedron_cameras(1), *renderer).face;
  expect_every_promise(GetParam(), input, before, vg, false);
  EXPECT_EQ(input.faces, copy.faces);  // input never modified
  EXPECT_EQ(input.positions.size(), copy.positions.size());
}

INSTANTIATE_TEST_SUITE_P(Meshes, RealMeshInvariants, ::testing::ValuesIn(test::real_mesh_paths()),
                         [](const auto& param_info) {
                           const std::string& path = param_info.param;
                           std::string name = path.substr(path.find_last_of('/') + 1);
                           name = name.substr(0, name.find('.'));
                           return name;
                         });

// Library errors name struct fields and point at the member, so the apps can name their own
// flag; no command-line flag appears in the library's words.
TEST(SimplifyOptions, ErrorsNameTheFieldNotAFlag) {
  SimplifyOptions o;
  o.target_ratio = 0.5;
  o.max_normal_change_deg = 200;
  try {
    check_options(o);
    ADD_FAILURE();
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), &o.max_normal_change_deg);
    EXPECT_NE(std::string(e.what()).find("SimplifyOptions::max_normal_change_deg"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
  SimplifyOptions no_target;
  try {
    check_options(no_target);
    ADD_FAILURE();
  } catch (const OptionError& e) {
    EXPECT_EQ(e.field(), nullptr);  // several fields: none to point at
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
}

// A CollapseCost replaces the queue order; weights follow merges by max. A vertex whose
// weight makes every edge at it expensive outlives the others.
class WeightedLengthCost final : public CollapseCost {
 public:
  double cost(const Edge& e) const override { return norm(e.p1 - e.p0) * (1e-3 + e.w0 + e.w1); }
};

TEST(Simplify, ACollapseCostOrdersTheQueueAndWeightsFollowMerges) {
  const Mesh grid = test::grid(16);
  const VertexIndex protected_vertex = 8 * 17 + 8;  // the centre of the grid
  const WeightedLengthCost cost;
  SimplifyOptions options;
  options.target_faces = grid.num_faces() / 4;
  options.collapse_cost = &cost;
  options.vertex_weights.assign(grid.num_vertices(), 0.0f);
  options.vertex_weights[protected_vertex] = 1000.0f;
  const Mesh out = simplify(grid, options).mesh;
  EXPECT_LE(out.num_faces(), options.target_faces);
  bool kept = false;
  for (const Vec3& p : out.positions) kept |= p.x == 8 && p.y == 8 && p.z == 0;
  EXPECT_TRUE(kept);
  // The order is the cost's, not the quadrics': QB to the same count keeps other vertices.
  SimplifyOptions qb;
  qb.target_faces = options.target_faces;
  const Mesh plain = simplify(grid, qb).mesh;
  EXPECT_NE(plain.positions, out.positions);
  // A wrong number of weights is refused.
  options.vertex_weights.pop_back();
  EXPECT_THROW(simplify(grid, options), OptionError);
}

// The engine works in its own spatial order (vertices along a Morton curve); what it returns
// is in the input's: kept input vertices in increasing input index, faces in increasing input
// face index (their quality travels with them), positions bit-exact where no collapse moved them.
// simplify(Mesh&&) only saves memory: the same mesh, qualities and result as from a copy.
// simplify(Mesh&&) drops the input's faces after set-up and, when every coordinate is a float
// (the bunny's PLY), keeps the positions as floats: the same output either way, bit for bit,
// including the vertices that kept their input position; also for coordinates that are not
// floats (the bunny scaled by 1/3), which stay doubles.
TEST(Simplify, GivingUpTheInputGivesTheSameResult) {
  Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  for (std::size_t f = 0; f < bunny.num_faces(); ++f) bunny.face_quality.push_back(float(f % 5));
  for (std::size_t v = 0; v < bunny.num_vertices(); ++v) bunny.vertex_quality.push_back(float(v % 3));
  Mesh third = bunny;
  for (Vec3& p : third.positions) p = p / 3.0;
  SimplifyOptions o;
  for (const Mesh* input : {&bunny, &third}) {
    for (const double ratio : {0.1, 0.8}) {
      o.target_ratio = ratio;
      const Simplified kept = simplify(*input, o);
      Mesh given = *input;
      const Simplified moved = simplify(std::move(given), o);
      EXPECT_EQ(moved.mesh.positions, kept.mesh.positions);
      EXPECT_EQ(moved.mesh.faces, kept.mesh.faces);
      EXPECT_EQ(moved.mesh.face_quality, kept.mesh.face_quality);
      EXPECT_EQ(moved.mesh.vertex_quality, kept.mesh.vertex_quality);
      EXPECT_EQ(moved.result.collapses, kept.result.collapses);
      EXPECT_EQ(moved.result.faces_in, input->num_faces());
      const std::size_t unmoved = static_cast<std::size_t>(
          std::count_if(moved.mesh.positions.begin(), moved.mesh.positions.end(), [&](const Vec3& p) {
            return std::find(input->positions.begin(), input->positions.end(), p) != input->positions.end();
          }));
      if (ratio > 0.5) {
        EXPECT_GT(unmoved, moved.mesh.num_vertices() / 4) << "at 80% many vertices keep their input position";
      }
    }
  }
  // Already at its target: the mesh itself comes back.
  o.target_ratio = 1.0;
  Mesh whole = bunny;
  const Simplified same = simplify(std::move(whole), o);
  EXPECT_EQ(same.mesh.faces, bunny.faces);
  EXPECT_EQ(same.result.stop_reason, StopReason::nothing_to_do);
}

TEST(Simplify, OutputKeepsTheInputOrderWhateverTheEngineOrder) {
  Mesh mesh = read_mesh(test::bundled_mesh("bunny.ply"));
  mesh.face_quality.resize(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) mesh.face_quality[f] = static_cast<float>(f);
  mesh.vertex_quality.resize(mesh.num_vertices());
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) mesh.vertex_quality[v] = static_cast<float>(v);
  SimplifyOptions options;
  options.target_ratio = 0.3;
  const Mesh out = simplify(mesh, options).mesh;
  ASSERT_EQ(out.face_quality.size(), out.num_faces());
  ASSERT_EQ(out.vertex_quality.size(), out.num_vertices());
  for (std::size_t f = 1; f < out.num_faces(); ++f) ASSERT_LT(out.face_quality[f - 1], out.face_quality[f]);
  std::size_t exact = 0;
  for (std::size_t v = 0; v < out.num_vertices(); ++v) {
    if (v > 0) {
      ASSERT_LT(out.vertex_quality[v - 1], out.vertex_quality[v]);
    }
    exact += out.positions[v] == mesh.positions[static_cast<std::size_t>(out.vertex_quality[v])] ? 1 : 0;
  }
  EXPECT_GT(exact, 0u);  // vertices no collapse moved keep their own input coordinates, bit for bit
  // Reversing the input's vertex order renames vertices, nothing else: the same surface
  // comes out (up to the queue's ties, which the engine breaks in its own order).
  Mesh reversed = mesh;
  const auto last = static_cast<VertexIndex>(mesh.num_vertices() - 1);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) reversed.positions[v] = mesh.positions[last - v];
  for (Face& f : reversed.faces)
    for (VertexIndex& v : f) v = last - v;
  const Mesh out_reversed = simplify(reversed, options).mesh;
  EXPECT_EQ(out_reversed.num_faces(), out.num_faces());
  EXPECT_NEAR(surface_distance(out_reversed, out).hausdorff, 0.0, 1e-3 * bounding_box(mesh).diagonal());
}

}  // namespace
}  // namespace visimp
