// Per-cell LODs, cell files and the walk (walkthrough-LOD paper; docs/cells.md).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/cells/cell_lod.h"
#include "visimp/cells/cell_store.h"
#include "visimp/cells/lod_cost.h"
#include "visimp/cells/walk.h"
#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"
#include "visimp/simplify/simplify.h"

namespace visimp {
namespace {

Transform translate(double x, double y, double z, double s = 1) {
  return {s, 0, 0, x, 0, s, 0, y, 0, 0, s, z, 0, 0, 0, 1};
}

// Spheres around a cell of size 5 at the origin (eye height 1): one inside it, one next to
// it, one far away.
Scene three_spheres() {
  Scene scene;
  scene.meshes.push_back(test::icosphere(3, 1.0));
  scene.mesh_paths.push_back("sphere");
  scene.objects.push_back({"inside", 0, translate(1, 0, 1)});
  scene.objects.push_back({"near", 0, translate(9, 0, 1, 2)});
  scene.objects.push_back({"far", 0, translate(300, 40, 1, 3)});
  return scene;
}

CellBuildOptions small_options() {
  CellBuildOptions o;
  o.output_resolution = 256;
  o.max_capture_resolution = 256;
  return o;
}

TEST(CellLod, InsideObjectsStayWholeAndTsDecidesSvMeshOrMvMesh) {
  const Scene scene = three_spheres();
  const HexGrid grid(5, 1);
  CellBuildOptions options = small_options();
  const CellLods lods = CellLodBuilder(scene, grid, options).build({0, 0});
  ASSERT_EQ(lods.entries.size(), 3u);
  // Inside: the sphere less what regional culling drops (a sphere beside the eye shows
  // most of itself to the cell, but not all).
  EXPECT_EQ(lods.entries[0].kind, LodKind::full);
  EXPECT_GT(lods.entries[0].faces.size(), scene.meshes[0].num_faces() / 2);
  EXPECT_LE(lods.entries[0].faces.size(), scene.meshes[0].num_faces());
  // Next to the cell, holes from the corners are many pixels wide: an MVMesh. Far away, s is
  // at most a pixel: an SVMesh, and a small one.
  EXPECT_EQ(lods.entries[1].kind, LodKind::mvmesh);
  EXPECT_GT(lods.entries[1].self_occluding_error, options.ts_pixels);
  EXPECT_EQ(lods.entries[2].kind, LodKind::svmesh);
  EXPECT_LE(lods.entries[2].self_occluding_error, 1.0f);
  EXPECT_LT(lods.entries[2].mesh.num_faces(), scene.meshes[0].num_faces() / 8);
  EXPECT_GT(lods.entries[2].mesh.num_faces(), 0u);
  // Ts above the near sphere's s makes it an SVMesh too: the test alone decides.
  options.ts_pixels = lods.entries[1].self_occluding_error + 1;
  const CellLods tolerant = CellLodBuilder(scene, grid, options).build({0, 0});
  EXPECT_EQ(tolerant.entries[1].kind, LodKind::svmesh);
  EXPECT_EQ(tolerant.entries[2].kind, LodKind::svmesh);
  // An SVMesh keeps only faces front-facing to the centre: fewer than the MVMesh's.
  EXPECT_LT(tolerant.entries[1].mesh.num_faces(), lods.entries[1].mesh.num_faces());
}

TEST(CellLod, ClusteringSharesAnSvMeshAndCullsWhatTheClusterHides) {
  Scene scene;
  scene.meshes.push_back(test::icosphere(3, 1.0));
  scene.mesh_paths.push_back("sphere");
  scene.objects.push_back({"front", 0, translate(200, 0, 1, 3)});
  scene.objects.push_back({"behind", 0, translate(230, 0, 1, 2.5)});  // hidden by "front" from the centre
  scene.objects.push_back({"aside", 0, translate(0, 200, 1, 3)});
  const HexGrid grid(5, 1);
  CellBuildOptions options = small_options();
  options.output_resolution = 1024;  // the spheres ~25 pixels across, so their SVMeshes keep some faces
  const CellLods alone = CellLodBuilder(scene, grid, options).build({0, 0});
  options.clustering = true;
  const CellLods clustered = CellLodBuilder(scene, grid, options).build({0, 0});
  for (const CellEntry& e : alone.entries) EXPECT_EQ(e.kind, LodKind::svmesh);
  EXPECT_EQ(clustered.entries[0].kind, LodKind::svmesh);
  EXPECT_EQ(clustered.entries[0].cluster, (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(clustered.entries[1].kind, LodKind::in_cluster);
  EXPECT_EQ(clustered.entries[1].cluster, (std::vector<std::uint32_t>{0}));
  EXPECT_EQ(clustered.entries[2].kind, LodKind::svmesh);  // its projection meets no other
  EXPECT_TRUE(clustered.entries[2].cluster.empty());
  // The hidden sphere costs (almost) nothing any more.
  EXPECT_LT(clustered.entries[0].mesh.num_faces(),
            alone.entries[0].mesh.num_faces() + alone.entries[1].mesh.num_faces() / 4);
  EXPECT_LT(clustered.faces(), alone.faces());
  // Clusters survive the file; a member its holder does not list is refused.
  const test::TempDir dir("cluster_file");
  const std::uint64_t hash = hash_scene(scene);
  write_cell(clustered, hash, dir.path() + "/c.vcell");
  const CellLods back = read_cell(dir.path() + "/c.vcell", scene, hash, {0, 0});
  EXPECT_EQ(back.entries[0].cluster, clustered.entries[0].cluster);
  EXPECT_EQ(back.entries[1].kind, LodKind::in_cluster);
  CellLods broken = clustered;
  broken.entries[0].cluster = {0};
  write_cell(broken, hash, dir.path() + "/b.vcell");
  EXPECT_THROW(read_cell(dir.path() + "/b.vcell", scene, hash, {0, 0}), IoError);
}

TEST(CellLod, ASmallerTlKeepsMoreFaces) {
  const Scene scene = three_spheres();
  const HexGrid grid(5, 1);
  std::vector<std::size_t> faces;
  for (const double tl : {0.25, 1.5, 8.0}) {
    CellBuildOptions options = small_options();
    options.tl_pixels = tl;
    options.base_levels = 0;  // from the full sphere each time
    faces.push_back(CellLodBuilder(scene, grid, options).build({0, 0}).entries[2].mesh.num_faces());
  }
  EXPECT_GT(faces[0], faces[1]);
  EXPECT_GT(faces[1], faces[2]);
}

// A cost that refuses every collapse: the run stops at once, by the cost's own rule.
class RefuseAll final : public CollapseCost {
 public:
  double cost(const Edge&) const override { return std::numeric_limits<double>::infinity(); }
};

TEST(CellLod, AnInfiniteCostRefusesTheCollapse) {
  const Mesh sphere = test::icosphere(2);
  const RefuseAll refuse;
  SimplifyOptions options;
  options.target_faces = 1;
  options.collapse_cost = &refuse;
  const Simplified out = simplify(sphere, options);
  EXPECT_EQ(out.result.collapses, 0u);
  EXPECT_EQ(out.result.stop_reason, StopReason::error_limit);
  EXPECT_EQ(out.mesh.num_faces(), sphere.num_faces());
  // The Tl rule: edges longer than the tolerance (radians from the eye) are never collapsed.
  const ProjectedLengthCost tl({Vec3{0, 0, 10}}, 0.05);
  EXPECT_TRUE(std::isinf(tl.cost({0, 1, {0, 0, 0}, {1, 0, 0}, {0.5, 0, 0}, {0, 0, 1}, {0, 0, 1}, 1, 1})));
  EXPECT_TRUE(std::isfinite(tl.cost({0, 1, {0, 0, 0}, {0.1, 0, 0}, {0.05, 0, 0}, {0, 0, 1}, {0, 0, 1}, 1, 1})));
}

TEST(CellLod, MvMeshLengthsHoldForEveryEyeInTheCell) {
  // An edge facing the middle of a hexagon's side is nearer to it than to any corner.
  const HexGrid grid(10, 0);
  const auto corners = grid.corners({0, 0});
  const Vec3 mid = (corners[1] + corners[2]) * 0.5;  // a side's midpoint
  const Vec3 out = mid * (1 + 2 / norm(mid));        // 2 units out from it
  EXPECT_NEAR(distance_to_hexagon(corners, out), 2, 1e-9);
  EXPECT_EQ(distance_to_hexagon(corners, Vec3{0, 0, 0}), 0);
  EXPECT_NEAR(distance_to_hexagon(corners, Vec3{0, 0, 3}), 3, 1e-12);
  std::vector<Vec3> eyes{Vec3{0, 0, 0}};
  eyes.insert(eyes.end(), corners.begin(), corners.end());
  ProjectedLengthCost cost(eyes);
  const Vec3 a = out + Vec3{0, 0, -0.05}, b = out + Vec3{0, 0, 0.05};
  const double corner_only = cost.projected_length(a, b);
  cost.set_region(corners);
  EXPECT_NEAR(cost.projected_length(a, b), 0.1 / 2, 1e-3);
  EXPECT_GT(cost.projected_length(a, b), 1.5 * corner_only);
}

TEST(CellStore, CellFilesRoundTripAndRefuseDamage) {
  const Scene scene = three_spheres();
  const HexGrid grid(5, 1);
  const CellLods lods = CellLodBuilder(scene, grid, small_options()).build({0, 0});
  const test::TempDir dir("cell_store");
  const std::uint64_t hash = hash_scene(scene);
  const std::string path = dir.path() + "/" + cell_file_name({0, 0});
  write_cell(lods, hash, path);
  const CellLods back = read_cell(path, scene, hash, {0, 0});
  ASSERT_EQ(back.entries.size(), lods.entries.size());
  for (std::size_t i = 0; i < lods.entries.size(); ++i) {
    const CellEntry &a = lods.entries[i], &b = back.entries[i];
    EXPECT_EQ(a.kind, b.kind);
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(a.mesh.faces, b.mesh.faces);
    ASSERT_EQ(a.mesh.num_vertices(), b.mesh.num_vertices());
    for (std::size_t v = 0; v < a.mesh.num_vertices(); ++v)
      EXPECT_LT(norm(a.mesh.positions[v] - b.mesh.positions[v]), 1e-5 * 300);
    EXPECT_EQ(a.self_occluding_error, b.self_occluding_error);
    ASSERT_EQ(a.textures.size(), b.textures.size());
    for (std::size_t t = 0; t < a.textures.size(); ++t) {
      EXPECT_EQ(a.textures[t].y, b.textures[t].y);
      EXPECT_EQ(a.textures[t].depth, b.textures[t].depth);
      EXPECT_EQ(a.textures[t].width, b.textures[t].width);
      EXPECT_EQ(a.textures[t].view.eye.x, b.textures[t].view.eye.x);
    }
  }
  // One texture per SVMesh (the centre), seven per MVMesh (centre and corners).
  EXPECT_EQ(lods.entries[1].textures.size(), 7u);
  EXPECT_EQ(lods.entries[2].textures.size(), 1u);
  EXPECT_EQ(cell_file_name({-3, 12}), "cell_m3_12.vcell");

  const std::string bytes = read_file_bytes(path);
  auto refused = [&](const std::string& changed, const Scene& s, const HexCell& cell, const std::string& needle) {
    const std::string p = dir.path() + "/bad.vcell";
    std::ofstream(p, std::ios::binary) << changed;
    try {
      read_cell(p, s, hash_scene(s), cell);
      ADD_FAILURE() << "accepted; expected '" << needle << "'";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.vcell"), std::string::npos) << e.what();
    }
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  refused(flipped, scene, {0, 0}, "corrupt");
  refused(bytes.substr(0, bytes.size() - 20), scene, {0, 0}, "corrupt");
  refused(bytes.substr(0, 10), scene, {0, 0}, "truncated");
  refused("not a cell file at all", scene, {0, 0}, "bad magic");
  std::string version = bytes;
  version[8] = 2;
  refused(version, scene, {0, 0}, "version 2");
  refused(bytes, scene, {1, 0}, "expected (1, 0)");
  Scene moved = scene;
  moved.objects[2].transform[3] += 1;
  refused(bytes, moved, {0, 0}, "another scene");
}

TEST(CellStore, ManifestsRoundTripAndRefuseOtherFiles) {
  const test::TempDir dir("cell_manifest");
  CellManifest m;
  m.scene_hash = 0xfedcba9876543210ull;
  m.objects = 3;
  m.cell_size = 7.5;
  m.eye_height = 2;
  m.cells = {{0, 0}, {-1, 2}};
  m.cell_faces = {10, 20};
  m.cell_seconds = {0.5, 0.25};
  m.options.tl_pixels = 3.75;  // not the default, so the round trip is seen
  write_manifest(m, dir.path() + "/cells.json");
  const CellManifest back = read_manifest(dir.path() + "/cells.json");
  EXPECT_EQ(back.scene_hash, m.scene_hash);
  EXPECT_EQ(back.cells.size(), 2u);
  EXPECT_EQ(back.cells[1], (HexCell{-1, 2}));
  EXPECT_EQ(back.cell_size, 7.5);
  EXPECT_EQ(back.options.tl_pixels, 3.75);
  for (const char* text : {"{", "{\"format\": \"visimp-scene\", \"version\": 1}",
                           "{\"format\": \"visimp-cells\", \"version\": 2}",
                           "{\"format\": \"visimp-cells\", \"version\": 1, \"scene_hash\": \"zz\"}"}) {
    std::ofstream(dir.path() + "/bad.json") << text;
    EXPECT_THROW(read_manifest(dir.path() + "/bad.json"), IoError) << text;
  }
  EXPECT_THROW(read_manifest(dir.path() + "/missing.json"), IoError);
}

TEST(Walk, PsnrAndFrustumCullingAreExact) {
  FrameImage a, b;
  a.resolution = b.resolution = 2;
  a.y = {0, 0, 0, 0};
  b.y = {255, 0, 0, 0};
  EXPECT_NEAR(psnr(a, b), 10 * std::log10(4.0), 1e-12);
  EXPECT_TRUE(std::isinf(psnr(a, a)));
  // Culling whole groups by their spheres never changes the image.
  const Scene scene = three_spheres();
  const RenderSet set = full_scene_set(scene);
  PerspectiveRasterizer raster;
  PerspectiveFrame scratch;
  FrameImage culled, all;
  std::size_t fewer = 0;
  for (int k = 0; k < 24; ++k) {
    const double t = k * M_PI / 12;
    const CameraPose pose{{-2, 0, 1}, {std::cos(t), std::sin(t), 0.1}};
    const PerspectiveView view = frame_view(pose, 60, 96, 0.01);
    const std::size_t n_culled = render_frame(set, view, true, Shading::smooth, false, raster, scratch, culled);
    const std::size_t n_all = render_frame(set, view, false, Shading::smooth, false, raster, scratch, all);
    EXPECT_EQ(culled.y, all.y) << k;
    EXPECT_LE(n_culled, n_all);
    if (n_culled < n_all) ++fewer;
  }
  EXPECT_GT(fewer, 12u);  // looking away from objects drops them
}

TEST(Walk, PrefetchingNeverChangesWhatIsDrawn) {
  const Scene scene = three_spheres();
  const HexGrid grid(5, 1);
  const test::TempDir dir("walk");
  // A path through four cells, built with their neighbours.
  std::vector<CameraPose> path;
  for (int k = 0; k < 60; ++k) path.push_back({{-18 + 0.6 * k, 0.3, 1}, {1, 0.2, 0}});
  CellManifest manifest;
  manifest.scene_hash = hash_scene(scene);
  manifest.objects = scene.objects.size();
  manifest.cell_size = 5;
  manifest.eye_height = 1;
  manifest.options = small_options();
  const CellLodBuilder builder(scene, grid, manifest.options);
  for (const CameraPose& p : path) {
    const HexCell c = grid.cell_of(p.position.x, p.position.y);
    std::vector<HexCell> ring{c};
    for (const HexCell& n : grid.neighbours(c)) ring.push_back(n);
    for (const HexCell& r : ring) {
      if (std::find(manifest.cells.begin(), manifest.cells.end(), r) != manifest.cells.end()) continue;
      manifest.cells.push_back(r);
      write_cell(builder.build(r), manifest.scene_hash, dir.path() + "/" + cell_file_name(r));
    }
  }
  write_manifest(manifest, dir.path() + "/cells.json");
  WalkOptions options;
  options.resolution = 64;
  options.reference_every = 4;
  options.prefetch = true;
  const std::vector<WalkFrame> with = walk(scene, dir.path(), manifest, path, options);
  options.prefetch = false;
  const std::vector<WalkFrame> without = walk(scene, dir.path(), manifest, path, options);
  ASSERT_EQ(with.size(), without.size());
  std::size_t crossings = 0;
  for (std::size_t k = 0; k < with.size(); ++k) {
    EXPECT_EQ(with[k].image_hash, without[k].image_hash) << k;
    EXPECT_EQ(with[k].faces_c, without[k].faces_c) << k;
    EXPECT_EQ(with[k].cell, without[k].cell);
    crossings += with[k].crossing ? 1 : 0;
    if (k % 4 == 0) {
      EXPECT_GT(with[k].psnr, 20) << k;  // the LODs look like the scene
      EXPECT_GE(with[k].faces_a, with[k].faces_c);
    }
  }
  EXPECT_GE(crossings, 4u);  // the first frame and three crossings
  // A path leaving the built cells is refused, naming the cell.
  const std::vector<CameraPose> away{{{500, 500, 1}, {1, 0, 0}}};
  EXPECT_THROW(walk(scene, dir.path(), manifest, away, options), IoError);
}

TEST(Textures, ATextureGivesBackWhatItSawAndOnlyThat) {
  const Scene scene = three_spheres();
  RenderSet sphere;
  sphere.add(scene.object_mesh(1), nullptr, 1);  // radius 2 at (9, 0, 1)
  sphere.finish();
  const Vec3 eye{0, 0, 1}, centre{9, 0, 1};
  const ProjectiveTexture tex = capture_texture(sphere, eye, centre, 2, 128);
  ASSERT_GT(tex.width, 64);
  EXPECT_LE(tex.width, 128);
  // The near side's centre is seen; the far side's is not (the sphere hides it).
  float grey = -1;
  EXPECT_TRUE(tex.sample(Vec3{7, 0, 1}, 0.02, &grey));
  EXPECT_GT(grey, 0);
  EXPECT_FALSE(tex.sample(Vec3{11, 0, 1}, 0.02, &grey));
  EXPECT_FALSE(tex.sample(Vec3{9, 5, 1}, 0.02, &grey));  // outside the crop
  // Drawn textured from near where it was captured, a much coarser flat-shaded sphere looks
  // like the fine one inside its outline (the outline is the geometry's: textures cannot help).
  RenderSet fine = sphere, coarse, textured;
  Mesh low = test::icosphere(1, 2.0);
  for (Vec3& p : low.positions) p = p + centre;
  coarse.add(low, nullptr, 1);
  coarse.finish();
  textured = coarse;
  textured.groups[0].textures.push_back(tex);
  PerspectiveRasterizer raster;
  PerspectiveFrame scratch;
  FrameImage reference, plain, mapped;
  const PerspectiveView view = PerspectiveView::looking_at(eye + Vec3{0, 0.3, 0}, centre, 40, 128, 0.01);
  render_frame(fine, view, false, Shading::smooth, false, raster, scratch, reference);
  render_frame(coarse, view, false, Shading::flat, false, raster, scratch, plain);
  render_frame(textured, view, false, Shading::flat, true, raster, scratch, mapped);
  double plain_error = 0, mapped_error = 0;
  std::size_t inside = 0;
  for (std::size_t p = 0; p < reference.y.size(); ++p) {
    if (reference.y[p] == kBackgroundGrey || plain.y[p] == kBackgroundGrey) continue;
    plain_error += std::abs(reference.y[p] - plain.y[p]);
    mapped_error += std::abs(reference.y[p] - mapped.y[p]);
    ++inside;
  }
  ASSERT_GT(inside, 2000u);
  EXPECT_LT(mapped_error / static_cast<double>(inside), 3.0);  // grey levels of 255
  EXPECT_LT(mapped_error, 0.25 * plain_error);
}

TEST(Scene, ObjGroupsAreTheObjects) {
  const test::TempDir dir("obj_groups");
  const std::string path = dir.path() + "/two.obj";
  // Two groups; the second is two triangles that share no vertex (two components, one object).
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\nv 9 0 0\nv 9 1 0\nv 9 0 1\n"
                         "o left\nf 1 2 3\ng right part\nf 4 5 6\nf 7 8 9\n";
  const Scene scene = read_scene(path);
  ASSERT_EQ(scene.objects.size(), 2u);
  EXPECT_EQ(scene.objects[0].name, "left");
  EXPECT_EQ(scene.objects[1].name, "right part");
  EXPECT_EQ(scene.meshes[scene.objects[1].mesh].num_faces(), 2u);
  // Without groups, the components are the objects, as for any mesh file.
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 1 2 3\nf 4 5 6\n";
  EXPECT_EQ(read_scene(path).objects.size(), 2u);
  std::ofstream(path) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  EXPECT_THROW(read_scene(path), IoError);
}

TEST(Walk, CameraPathsAreReadStrictly) {
  const test::TempDir dir("path");
  const std::string good = dir.path() + "/good.txt";
  std::ofstream(good) << "# a path\n0 0 1.7 1 0 0\n\n  5 0 1.7 1 1 0  # turning\n";
  const auto path = read_camera_path(good);
  ASSERT_EQ(path.size(), 2u);
  EXPECT_EQ(path[1].position.x, 5);
  for (const char* bad : {"0 0 1 1 0\n", "0 0 1 1 0 0 7\n", "0 0 1 0 0 0\n", "a b c d e f\n", "# nothing\n",
                          "0 0 nan 1 0 0\n"}) {
    const std::string p = dir.path() + "/bad.txt";
    std::ofstream(p) << bad;
    EXPECT_THROW(read_camera_path(p), IoError) << bad;
  }
  const auto loop = auto_camera_path(three_spheres(), 1, 50);
  EXPECT_EQ(loop.size(), 50u);
  for (const CameraPose& p : loop) EXPECT_EQ(p.position.z, 1);
}

// The auto loop walks around objects on its ellipse instead of through them (frames from inside
// a solid compare back faces the cells rightly cull), and stays on the ellipse elsewhere.
TEST(Walk, AutoPathWalksAroundObjects) {
  Scene scene;
  scene.meshes.push_back(test::icosphere(3, 1.0));
  scene.mesh_paths.push_back("sphere");
  // Two markers span x, y in [-1, 101]: the ellipse is centred at (50, 50) with semi-axes 35.7.
  scene.objects.push_back({"corner", 0, translate(0, 0, 1)});
  scene.objects.push_back({"corner", 0, translate(100, 100, 1)});
  // Two statues of radius 5 right on it, at t = 0 and t = 90 degrees.
  const double a = 0.35 * 102;
  scene.objects.push_back({"statue", 0, translate(50 + a, 50, 5, 5)});
  scene.objects.push_back({"statue", 0, translate(50, 50 + a, 5, 5)});
  const auto loop = auto_camera_path(scene, 2, 400);
  ASSERT_EQ(loop.size(), 400u);
  std::size_t detoured = 0;
  for (const CameraPose& p : loop) {
    for (const Vec3& c : {Vec3{50 + a, 50, 0}, Vec3{50, 50 + a, 0}})
      EXPECT_GE(std::hypot(p.position.x - c.x, p.position.y - c.y), 5 * 1.1 * (1 - 1e-3));  // icosphere radius 1
    const double r = std::hypot((p.position.x - 50) / a, (p.position.y - 50) / a);
    if (std::abs(r - 1) > 1e-9) ++detoured;
    EXPECT_EQ(p.position.z, 2);
  }
  // Each statue blocks ~2 x 5.5 / (2 pi 35.7) of the loop: about 20 poses each.
  EXPECT_GT(detoured, 20u);
  EXPECT_LT(detoured, 60u);
}

}  // namespace
}  // namespace visimp
