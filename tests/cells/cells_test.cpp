// Scenes, hexagonal cells and regional back-face culling (walkthrough-LOD paper; docs/cells.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/cells/hex_grid.h"
#include "visimp/cells/lod_cost.h"
#include "visimp/cells/regional_culling.h"
#include "visimp/cells/scene.h"
#include "visimp/cells/view_weights.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/portable_random.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

TEST(HexGrid, EveryPointIsInTheOneCellThatClaimsIt) {
  for (const double size : {1.0, 37.5, 1e-3}) {
    const HexGrid grid(size, 1.7, 1e6 * size, -3e5 * size);  // far from the origin, too
    SplitMix64 random(7);
    for (int k = 0; k < 20000; ++k) {
      const double x = 1e6 * size + (random.uniform() - 0.5) * 40 * size;
      const double y = -3e5 * size + (random.uniform() - 0.5) * 40 * size;
      const HexCell c = grid.cell_of(x, y);
      ASSERT_TRUE(grid.contains(c, x, y)) << x << "," << y;
      // No neighbour is nearer (the Voronoi rule), and an equally near one loses the tie.
      const auto pc = grid.center(c);
      const double dc = std::hypot(x - pc[0], y - pc[1]);
      for (const HexCell& n : grid.neighbours(c)) {
        const auto pn = grid.center(n);
        const double dn = std::hypot(x - pn[0], y - pn[1]);
        EXPECT_GE(dn, dc);
        if (dn == dc) {
          EXPECT_TRUE(c.r < n.r || (c.r == n.r && c.q < n.q)) << "tie at " << x << "," << y;
        }
      }
    }
  }
  // Centres, corners and edge midpoints: corners lie in three closed hexagons, midpoints in two.
  const HexGrid grid(2.0);
  for (int q = -3; q <= 3; ++q) {
    for (int r = -3; r <= 3; ++r) {
      const HexCell c{q, r};
      const auto p = grid.center(c);
      EXPECT_EQ(grid.cell_of(p[0], p[1]), c);
      const auto corners = grid.corners(c);
      for (int k = 0; k < 6; ++k) {
        const Vec3& a = corners[static_cast<std::size_t>(k)];
        const Vec3& b = corners[static_cast<std::size_t>((k + 1) % 6)];
        // On a corner or an edge: the owner is one of the hexagons meeting there (the
        // corner's coordinates carry rounding, so within 1e-12 of the size).
        const HexCell at_corner = grid.cell_of(a.x, a.y);
        const auto pa = grid.center(at_corner);
        EXPECT_NEAR(std::hypot(a.x - pa[0], a.y - pa[1]), 2.0, 1e-12);
        const double mx = 0.5 * (a.x + b.x), my = 0.5 * (a.y + b.y);
        const auto pm = grid.center(grid.cell_of(mx, my));
        EXPECT_NEAR(std::hypot(mx - pm[0], my - pm[1]), std::sqrt(3.0), 1e-12);
        EXPECT_NEAR(a.z, 1.7, 0);
      }
    }
  }
  EXPECT_THROW(HexGrid(0), OptionError);
  EXPECT_THROW(HexGrid(std::nan("")), OptionError);
}

TEST(HexGrid, NeighboursShareAnEdgeAndCoverageIsComplete) {
  const HexGrid grid(3.0);
  const HexCell c{2, -1};
  const auto p = grid.center(c);
  for (const HexCell& n : grid.neighbours(c)) {
    const auto q = grid.center(n);
    // Centres of edge neighbours are one apothem pair apart: √3 · size.
    EXPECT_NEAR(std::hypot(q[0] - p[0], q[1] - p[1]), std::sqrt(3.0) * 3.0, 1e-12);
    const double mx = 0.5 * (p[0] + q[0]), my = 0.5 * (p[1] + q[1]);
    EXPECT_TRUE(grid.contains(c, mx, my));
    EXPECT_TRUE(grid.contains(n, mx, my));
  }
  const std::vector<HexCell> cover = grid.cells_covering(-20, -10, 35, 18);
  SplitMix64 random(3);
  for (int k = 0; k < 5000; ++k) {
    const double x = -20 + 55 * random.uniform(), y = -10 + 28 * random.uniform();
    EXPECT_NE(std::find(cover.begin(), cover.end(), grid.cell_of(x, y)), cover.end());
  }
}

TEST(RegionalCulling, IsConservativeAgainstEyesSampledInTheCell) {
  // A sphere two cells away, a wall beside the cell, and random triangles around it.
  const HexGrid grid(5.0, 1.7);
  const HexCell cell{0, 0};
  Mesh scene = test::icosphere(3, 3.0);
  for (Vec3& p : scene.positions) p = p + Vec3{20, 4, 2};
  SplitMix64 random(11);
  for (int k = 0; k < 400; ++k) {
    const VertexIndex base = static_cast<VertexIndex>(scene.positions.size());
    const Vec3 c{(random.uniform() - 0.5) * 40, (random.uniform() - 0.5) * 40, random.uniform() * 6};
    for (int v = 0; v < 3; ++v)
      scene.positions.push_back(c + Vec3{random.uniform() - 0.5, random.uniform() - 0.5, random.uniform() - 0.5} * 4.0);
    scene.faces.push_back({base, base + 1, base + 2});
  }
  const std::vector<std::uint8_t> keep = regional_back_face_cull(scene, grid.corners(cell));
  std::size_t culled = 0;
  for (std::uint8_t k : keep) culled += k == 0;
  EXPECT_GT(culled, scene.num_faces() / 5);  // the far half of the sphere, at least
  // Brute force: every face front-facing from some eye in the hexagon is kept.
  const auto corners = grid.corners(cell);
  for (int k = 0; k < 3000; ++k) {
    // A random point of the hexagon: a random convex combination of a corner triangle fan.
    const int t = static_cast<int>(random.next() % 6);
    double a = random.uniform(), b = random.uniform();
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const auto c = grid.center(cell);
    const Vec3 centre{c[0], c[1], 1.7};
    const Vec3 eye = centre + (corners[static_cast<std::size_t>(t)] - centre) * a +
                     (corners[static_cast<std::size_t>((t + 1) % 6)] - centre) * b;
    for (std::size_t f = 0; f < scene.num_faces(); ++f) {
      const Vec3 n = face_normal_unnormalized(scene, scene.faces[f]);
      if (dot(n, eye - scene.positions[scene.faces[f][0]]) > 0) {
        ASSERT_EQ(keep[f], 1) << "face " << f;
      }
    }
  }
}

TEST(Scene, JsonRoundTripTransformsAndRefusals) {
  const test::TempDir dir("scene");
  const std::string bunny = test::bundled_mesh("bunny.ply");
  Scene scene;
  scene.mesh_paths = {bunny};
  scene.meshes = {read_mesh(bunny)};
  scene.objects.push_back({"a", 0, kIdentity});
  scene.objects.push_back({"mirrored", 0, {-2, 0, 0, 10, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1}});
  write_scene(scene, dir.path() + "/s.json");
  const Scene back = read_scene(dir.path() + "/s.json");
  ASSERT_EQ(back.objects.size(), 2u);
  EXPECT_EQ(back.meshes.size(), 1u);  // instances share one read
  EXPECT_EQ(back.objects[1].name, "mirrored");
  EXPECT_EQ(back.objects[1].transform, scene.objects[1].transform);
  EXPECT_EQ(back.face_count(), 2 * scene.meshes[0].num_faces());
  // The transform is applied, and a mirror is rewound so the surface still encloses +volume.
  const Mesh m = back.object_mesh(1);
  const Vec3 p0 = back.meshes[0].positions[5];
  EXPECT_NEAR(m.positions[5].x, -2 * p0.x + 10, 1e-9);
  auto volume = [](const Mesh& mesh) {
    double v = 0;
    for (const Face& f : mesh.faces) v += dot(mesh.positions[f[0]], cross(mesh.positions[f[1]], mesh.positions[f[2]]));
    return v / 6;
  };
  EXPECT_NEAR(volume(m), 8 * volume(back.meshes[0]), 1e-6 * std::abs(8 * volume(back.meshes[0])));

  auto refused = [&](const std::string& text, const std::string& expect) {
    try {
      parse_scene(text, dir.path() + "/bad.json");
      ADD_FAILURE() << text;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expect), std::string::npos) << e.what();
    }
  };
  refused("{", "not valid JSON");
  refused(R"({"format": "other", "version": 1, "objects": []})", "not a visimp scene");
  refused(R"({"format": "visimp-scene", "version": 2, "objects": []})", "version");
  refused(R"({"format": "visimp-scene", "version": 1, "objects": [{"name": "x"}]})", "object 0");
  refused(R"({"format": "visimp-scene", "version": 1, "objects": [{"mesh": ")" + bunny + R"(", "transform": [1, 2]}]})",
          "16 numbers");
  refused(R"({"format": "visimp-scene", "version": 1, "objects": [{"mesh": ")" + bunny +
              R"(", "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 1,0,0,1]}]})",
          "affine");
  EXPECT_THROW(parse_scene(R"({"format": "visimp-scene", "version": 1, "objects": [{"mesh": "missing.ply"}]})",
                           dir.path() + "/m.json"),
               IoError);
}

TEST(Scene, AMeshReadsAsASceneOfItsComponents) {
  const Scene teapot = read_scene(test::bundled_mesh("teapot.ply"));
  EXPECT_EQ(teapot.objects.size(), 3u);  // SOURCES.md: 3 components
  EXPECT_EQ(teapot.face_count(), read_mesh(test::bundled_mesh("teapot.ply")).num_faces());
}

TEST(Scene, ParksAreReproducibleUprightAndInsideTheirArea) {
  ParkOptions options;
  options.objects = 25;
  options.width = 100;
  options.depth = 60;
  const std::vector<std::string> meshes = {test::bundled_mesh("bunny.ply"), test::bundled_mesh("teapot.ply")};
  const Scene a = make_park(meshes, {false, false}, options), b = make_park(meshes, {false, false}, options);
  ASSERT_EQ(a.objects.size(), 25u);
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].transform, b.objects[i].transform);
    const Mesh placed = a.object_mesh(i);
    const Mesh& source = a.meshes[a.objects[i].mesh];
    const BoundingBox box = bounding_box(placed);
    EXPECT_NEAR(box.min.z, 0, 1e-9);
    // A similarity: distances scale by object_size · U(0.8, 1.2) / the source's diagonal.
    const double scale =
        norm(placed.positions[1] - placed.positions[0]) / norm(source.positions[1] - source.positions[0]);
    const double diagonal = bounding_box(source).diagonal() * scale;
    EXPECT_GT(diagonal, 0.79 * options.object_size);
    EXPECT_LT(diagonal, 1.21 * options.object_size);
    const Vec3 c = box.center();
    EXPECT_LE(std::abs(c.x), 50.0);
    EXPECT_LE(std::abs(c.y), 30.0);
  }
  options.seed = 2;
  EXPECT_NE(make_park(meshes, {false, false}, options).objects[0].transform, a.objects[0].transform);
}

TEST(ViewWeights, SilhouettesWeighMostAndHiddenVerticesNothing) {
  const Mesh sphere = test::icosphere(4);
  const Vec3 eye{0, -12, 0};
  const DepthImage image = capture_depth(sphere, eye, 256);
  const std::vector<float> w = depth_variation_weights(sphere, image);
  double rim = 0, facing = 0, back = 0;
  double n_rim = 0, n_facing = 0, n_back = 0;
  for (std::size_t v = 0; v < sphere.num_vertices(); ++v) {
    const Vec3& p = sphere.positions[v];  // the unit normal too
    const double c = dot(p, (eye - p) * (1 / norm(eye - p)));
    if (c > 0.7)
      facing += w[v], ++n_facing;
    else if (c > 0 && c < 0.05)
      rim += w[v], ++n_rim;
    else if (c < -0.3)
      back += w[v], ++n_back;
  }
  ASSERT_GT(n_rim, 10);
  EXPECT_GT(rim / n_rim, 0.6);
  EXPECT_LT(facing / n_facing, 0.2);
  EXPECT_EQ(back, 0.0);
  // A cube's visible edges are creases: their vertices weigh more than the faces' middles.
  const Mesh cube = test::subdivided_cube(8);
  const DepthImage cube_image = capture_depth(cube, {3.1, -2.3, 2.7}, 256);
  const std::vector<float> cw = depth_variation_weights(cube, cube_image);
  double edge = 0, middle = 0;
  double n_edge = 0, n_middle = 0;
  for (std::size_t v = 0; v < cube.num_vertices(); ++v) {
    const Vec3& p = cube.positions[v];
    // On the three visible faces x = 1, y = 0, z = 1: the edges between them, away from corners.
    const bool on_xz = std::abs(p.x - 1) < 1e-9 && std::abs(p.z - 1) < 1e-9 && p.y > 0.2 && p.y < 0.8;
    const bool mid = std::abs(p.z - 1) < 1e-9 && std::abs(p.x - 0.5) < 0.2 && std::abs(p.y - 0.5) < 0.2;
    if (on_xz) edge += cw[v], ++n_edge;
    if (mid) middle += cw[v], ++n_middle;
  }
  ASSERT_GT(n_edge, 0);
  ASSERT_GT(n_middle, 0);
  EXPECT_GT(edge / n_edge, middle / n_middle + 0.2);
}

TEST(ViewWeights, SelfOccludingErrorIsSmallFarAwayAndLargeNearby) {
  const HexGrid grid(5.0, 0.0);
  const HexCell cell{0, 0};
  const Vec3 centre = grid.eye_at_center(cell);
  const auto corners = grid.corners(cell);
  Mesh far = test::icosphere(3, 2.0), near = test::icosphere(3, 2.0);
  for (Vec3& p : far.positions) p = p + Vec3{0, 300, 0};
  for (Vec3& p : near.positions) p = p + Vec3{0, 9, 0};
  const double s_far = self_occluding_error(far, centre, corners, 256, 60);
  const double s_near = self_occluding_error(near, centre, corners, 256, 60);
  EXPECT_LE(s_far, 1.0);
  EXPECT_GE(s_near, 5.0);
  // With Ts = 2 px the far sphere takes an SVMesh, the near one an MVMesh.
  EXPECT_TRUE(s_far <= 2.0 && s_near > 2.0);
}

// Pixels where exactly one of two renders shows something, over the pixels the first shows.
double silhouette_difference(const Mesh& a, const Mesh& b, const PerspectiveView& view) {
  auto positions = [&](const Mesh& m) {
    std::vector<std::array<float, 3>> out;
    for (const Vec3& p : m.positions) {
      const Vec3 q = p - view.eye;
      out.push_back({float(q.x), float(q.y), float(q.z)});
    }
    return out;
  };
  PerspectiveView local = view;
  local.eye = Vec3{0, 0, 0};
  PerspectiveRasterizer raster;
  PerspectiveFrame fa, fb;
  raster.draw(positions(a), a.faces, nullptr, local, fa);
  raster.draw(positions(b), b.faces, nullptr, local, fb);
  double shown = 0, differ = 0;
  for (std::size_t p = 0; p < fa.ids.size(); ++p) {
    shown += fa.ids[p] != 0;
    differ += (fa.ids[p] != 0) != (fb.ids[p] != 0);
  }
  return differ / std::max(1.0, shown);
}

TEST(LodCost, TheSvMeshOfAFarObjectKeepsItsSilhouette) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  const BoundingBox box = bounding_box(bunny);
  const Vec3 centre = box.center() + Vec3{0.3, 0.2, 1} * (4 * box.diagonal());
  const DepthImage image = capture_depth(bunny, centre, 256);
  const std::vector<float> weights = depth_variation_weights(bunny, image);
  const std::size_t target = bunny.num_faces() / 8;
  const Mesh sv = build_lod_mesh(bunny, {centre}, weights, target);
  EXPECT_LE(sv.num_faces(), target);
  EXPECT_GE(sv.num_faces(), target - 2);
  // The same face count from plain quadrics on the same front-facing faces, for scale.
  SimplifyOptions qb;
  qb.target_faces = target;
  const Mesh front = build_lod_mesh(bunny, {centre}, weights, bunny.num_faces());
  const Mesh plain = simplify(front, qb).mesh;
  const double d_sv = silhouette_difference(bunny, sv, image.view);
  const double d_qb = silhouette_difference(bunny, plain, image.view);
  // Measured: 1.6% of the bunny's pixels with the paper's cost, 0.5% with plain quadrics (the
  // quadrics' placement error is the better guide to a silhouette here; docs/cells.md).
  std::printf("silhouette difference: paper cost %.4f, plain quadrics %.4f\n", d_sv, d_qb);
  EXPECT_LT(d_sv, 0.03);
  EXPECT_LT(d_qb, 0.03);
}

}  // namespace
}  // namespace visimp
