// The visibility field on tiny exact scenes (Blais & Poulin; docs/field.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/field/field.h"
#include "visimp/field/resample.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/perspective.h"
#include "visimp/render/ray_caster.h"

namespace visimp {
namespace {

void append(Mesh& scene, const Mesh& part, const Vec3& offset = {}, double scale = 1) {
  const VertexIndex base = static_cast<VertexIndex>(scene.positions.size());
  for (const Vec3& p : part.positions) scene.positions.push_back(p * scale + offset);
  for (const Face& f : part.faces) scene.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

// A wall in z = 0 over [-3, 3]² with a square window [-0.5, 0.5]², and a cube of side 0.8
// behind it (z in [-2, -1.2]) seen only through the window.
Mesh wall_with_window_and_box() {
  Mesh wall;
  const double o = 3, w = 0.5;
  wall.positions = {{-o, -o, 0}, {o, -o, 0}, {o, o, 0}, {-o, o, 0}, {-w, -w, 0}, {w, -w, 0}, {w, w, 0}, {-w, w, 0}};
  // Four trapezoids between the outer square (0..3) and the window (4..7), counter-clockwise from +z.
  for (VertexIndex k = 0; k < 4; ++k) {
    const VertexIndex a = k, b = (k + 1) % 4, c = 4 + (k + 1) % 4, d = 4 + k;
    wall.faces.push_back({a, b, c});
    wall.faces.push_back({a, c, d});
  }
  Mesh scene;
  append(scene, wall);
  append(scene, test::subdivided_cube(4), {-0.4, -0.4, -2.0}, 0.8);
  return scene;
}

bool any_marked(const std::vector<std::uint8_t>& marked, const CellPartition& cells, std::uint32_t object) {
  for (std::size_t c = 0; c < marked.size(); ++c) {
    if (marked[c] && cells.keys[c].object == object) return true;
  }
  return false;
}

PerspectiveView view_of(const VisibilityField& field, const Vec3& eye, const Vec3& look, double fov = 40) {
  return PerspectiveView::looking_at(eye, look, fov, 240, 1e-3 * field.box.diagonal());
}

TEST(Field, BoxBehindAWallIsMarkedOnlyThroughTheWindow) {
  const Mesh scene = wall_with_window_and_box();
  FieldOptions options;
  options.cells.grid = 4;
  const VisibilityField field = build_field(scene, options);
  ASSERT_EQ(field.cells.objects, 2u);
  const std::uint32_t box_object = field.cells.keys[field.cells.face_cell.back()].object;
  const FieldResampler resampler(field);
  const Vec3 box_centre{0, 0, -1.6};
  for (Interpolation interp : {Interpolation::None, Interpolation::UvSt}) {
    ResampleOptions r;
    r.interpolation = interp;
    r.subsample = 1;
    // In front of the window: the box shows through it.
    EXPECT_TRUE(
        any_marked(resampler.resample(view_of(field, {0, 0, 5}, box_centre), r).marked, field.cells, box_object))
        << interpolation_name(interp);
    EXPECT_TRUE(
        any_marked(resampler.resample(view_of(field, {0.3, -0.2, 8}, box_centre), r).marked, field.cells, box_object));
    // In front of the wall, away from the window: every line to the box crosses the wall.
    for (const Vec3& eye : {Vec3{5, 0, 3}, Vec3{0, -5, 3}, Vec3{-4, 4, 2}, Vec3{2.5, 2.5, 0.5}}) {
      const ResampleResult result = resampler.resample(view_of(field, eye, box_centre), r);
      EXPECT_GT(result.cells_marked, 0u);
      EXPECT_FALSE(any_marked(result.marked, field.cells, box_object))
          << "eye " << eye.x << "," << eye.y << "," << eye.z << " " << interpolation_name(interp);
    }
  }
}

TEST(Field, AboutHalfOfASpheresCellsAreMarkedFromOutside) {
  const Mesh sphere = test::icosphere(4);
  FieldOptions options;
  options.cells.grid = 8;
  options.ids = 5;
  const VisibilityField field = build_field(sphere, options);
  const VisibilityField one_id = build_field(sphere, [&] {
    FieldOptions o = options;
    o.ids = 1;
    return o;
  }());
  const FieldResampler resampler(field), one_id_resampler(one_id);
  ResampleOptions r;
  r.subsample = 1;
  for (const Vec3& eye : {Vec3{0, 0, 6}, Vec3{5, -3, 1}, Vec3{-4, -4, -4}}) {
    r.interpolation = Interpolation::UvSt;
    const ResampleResult result = resampler.resample(view_of(field, eye, {0, 0, 0}, 30), r);
    const double fraction = static_cast<double>(result.cells_marked) / static_cast<double>(field.cells.num_cells());
    // A viewer at distance d sees a cap of (1 − 1/d)/2 of the area; cells on its rim count too.
    EXPECT_GT(fraction, 0.35) << eye.x;
    EXPECT_LT(fraction, 0.65) << eye.x;
    // The paper's holes: one id and no post-filter mark fewer, never more.
    r.interpolation = Interpolation::None;
    const ResampleResult sparse = one_id_resampler.resample(view_of(field, eye, {0, 0, 0}, 30), r);
    EXPECT_LT(sparse.cells_marked, result.cells_marked);
    EXPECT_GT(sparse.cells_marked, field.cells.num_cells() / 10);
  }
}

TEST(Field, PreFilterRanksByCountTiesToTheSmallerId) {
  std::vector<std::uint32_t> hits = {5, 5, 5, 2, 2, 7, kNoCell, 2, 7, 7, 7, kNoCell, kNoCell, kNoCell, kNoCell};
  std::uint32_t out[5];
  rank_cells(hits, 5, out);
  // 7 ×4, then 2 and 5 ×3 each (2 first), misses never kept, the rest null; stored as id + 1.
  EXPECT_EQ(std::vector<std::uint32_t>(out, out + 5), (std::vector<std::uint32_t>{8, 3, 6, 0, 0}));
  std::vector<std::uint32_t> misses(81, kNoCell);
  rank_cells(misses, 2, out);
  EXPECT_EQ(out[0], 0u);
  EXPECT_EQ(out[1], 0u);
}

TEST(Field, PostFilteringNeverMarksFewerCells) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  FieldOptions options;
  options.ids = 2;
  const VisibilityField field = build_field(bunny, options);
  const FieldResampler resampler(field);
  const Vec3 c = field.box.center();
  const double d = field.box.diagonal();
  for (const Vec3& dir : {Vec3{0, 0, 1}, Vec3{1, 0.5, 0.2}, Vec3{-0.3, 1, -1}}) {
    const PerspectiveView view = view_of(field, c + dir * (1.5 * d / norm(dir)), c, 50);
    ResampleOptions r;
    const ResampleResult none = resampler.resample(view, r);
    for (Interpolation interp : {Interpolation::Uv, Interpolation::St, Interpolation::UvSt}) {
      r.interpolation = interp;
      const ResampleResult filtered = resampler.resample(view, r);
      for (std::size_t cell = 0; cell < none.marked.size(); ++cell) {
        if (none.marked[cell]) {
          ASSERT_TRUE(filtered.marked[cell]) << interpolation_name(interp) << " cell " << cell;
        }
      }
      EXPECT_GE(filtered.cells_marked, none.cells_marked);
    }
    r.interpolation = Interpolation::None;
    r.mip = -1;  // the mip-map reads coarser samples, never none of them
    EXPECT_GT(resampler.resample(view, r).cells_marked, 0u);
  }
}

TEST(Field, CellModesAndGroups) {
  const Mesh scene = wall_with_window_and_box();
  CellOptions polygon;
  polygon.mode = CellMode::Polygon;
  EXPECT_EQ(partition_cells(scene, polygon).num_cells(), scene.num_faces());
  CellOptions whole;
  whole.mode = CellMode::SceneGrid;
  whole.grid = 1;
  const CellPartition one = partition_cells(scene, whole);
  EXPECT_EQ(one.num_cells(), 1u);
  EXPECT_EQ(one.objects, 1u);
  CellOptions groups;
  groups.grid = 1;
  groups.face_objects.assign(scene.num_faces(), 3);
  EXPECT_EQ(partition_cells(scene, groups).num_cells(), 1u);
  groups.face_objects.pop_back();
  EXPECT_THROW(partition_cells(scene, groups), OptionError);
  // Every face is in exactly one cell, and the cell's box holds it.
  CellOptions grid;
  grid.grid = 5;
  const CellPartition cells = partition_cells(scene, grid);
  std::size_t listed = 0;
  for (std::size_t c = 0; c < cells.num_cells(); ++c) {
    for (std::uint32_t i = cells.cell_offsets[c]; i < cells.cell_offsets[c + 1]; ++i) {
      const std::uint32_t f = cells.cell_faces[i];
      EXPECT_EQ(cells.face_cell[f], c);
      for (VertexIndex v : scene.faces[f]) {
        EXPECT_GE(scene.positions[v].x, cells.bounds[c].min.x);
        EXPECT_LE(scene.positions[v].z, cells.bounds[c].max.z);
      }
      ++listed;
    }
  }
  EXPECT_EQ(listed, scene.num_faces());
}

TEST(Field, OptionsOutOfRangeNameTheirField) {
  const Mesh sphere = test::icosphere(1);
  for (auto [set, name] : std::vector<std::pair<void (*)(FieldOptions&), std::string>>{
           {[](FieldOptions& o) { o.cells.grid = 0; }, "CellOptions::grid"},
           {[](FieldOptions& o) { o.uv = 1; }, "FieldOptions::uv"},
           {[](FieldOptions& o) { o.st = 65; }, "FieldOptions::st"},
           {[](FieldOptions& o) { o.ids = 9; }, "FieldOptions::ids"},
           {[](FieldOptions& o) { o.slabs = 2; }, "FieldOptions::slabs"},
           {[](FieldOptions& o) { o.layers = 0; }, "FieldOptions::layers"}}) {
    FieldOptions o;
    set(o);
    try {
      build_field(sphere, o);
      ADD_FAILURE() << name << " accepted";
    } catch (const OptionError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(build_field(Mesh{}, FieldOptions{}), InvalidMeshError);
  ResampleOptions r;
  r.subsample = 3;
  EXPECT_THROW(check_options(r), OptionError);
}

TEST(Field, FileRoundTripAndRefusals) {
  const Mesh scene = wall_with_window_and_box();
  FieldOptions options;
  options.cells.grid = 3;
  options.uv = 4;
  options.st = 6;
  options.ids = 3;
  options.layers = 2;
  const VisibilityField field = build_field(scene, options);
  const test::TempDir dir("field_roundtrip");
  const std::string path = dir.path() + "/scene.vfd";
  const FieldFileSizes sizes = write_field_file(field, path);
  EXPECT_GT(sizes.compression_ratio(), 1.0);
  const VisibilityField back = read_field_file(path);
  EXPECT_EQ(back.mesh_hash, field.mesh_hash);
  EXPECT_EQ(back.samples, field.samples);
  EXPECT_EQ(back.cells.face_cell, field.cells.face_cell);
  EXPECT_EQ(back.cells.cell_faces, field.cells.cell_faces);
  EXPECT_EQ(back.interior, field.interior);
  EXPECT_EQ(back.slabs.size(), field.slabs.size());
  EXPECT_EQ(back.slabs[3].starts, field.slabs[3].starts);
  EXPECT_EQ(back.options.ids, 3);
  EXPECT_NO_THROW(check_field_matches(back, scene, path, "scene"));
  // A field of one mesh refuses another (content hash).
  Mesh moved = scene;
  moved.positions[0].x += 1e-3;
  EXPECT_THROW(check_field_matches(back, moved, path, "moved"), IoError);
  // Every truncation, a bad magic and a future version are refused with IoError, never a crash.
  const std::string bytes = read_file_bytes(path);
  for (std::size_t n = 0; n < bytes.size(); n += std::max<std::size_t>(1, bytes.size() / 300)) {
    EXPECT_THROW(parse_field_file(bytes.substr(0, n), "cut.vfd"), IoError) << n;
  }
  std::string bad = bytes;
  bad[0] = 'X';
  EXPECT_THROW(parse_field_file(bad, "magic.vfd"), IoError);
  bad = bytes;
  bad[8] = 2;
  try {
    parse_field_file(bad, "v2.vfd");
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("version 2"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_field_file(bytes + "x", "long.vfd"), IoError);
  // Slabs that do not follow from the box and options (a flipped bit in a start plane).
  const std::size_t slab_table = bytes.size() - 4096 - sizes.coded_sample_bytes - 8 * 2;
  bad = bytes;
  bad[slab_table] = static_cast<char>(bad[slab_table] ^ 0x10);
  EXPECT_THROW(parse_field_file(bad, "slab.vfd"), IoError);
}

TEST(Field, MipLevelsOddCountsFarViewsAndViewsAwayFromTheBox) {
  const Mesh sphere = test::icosphere(3);
  FieldOptions options;
  options.cells.grid = 6;
  options.uv = 5;  // odd counts: a coarse level's last sample holds one fine sample
  options.st = 7;
  options.ids = 2;
  const VisibilityField field = build_field(sphere, options);
  const FieldResampler resampler(field);
  ASSERT_GE(resampler.mip_levels(), 3);
  ResampleOptions r;
  r.subsample = 1;
  const PerspectiveView near_view = view_of(field, {0, 0, 5}, {0, 0, 0}, 40);
  EXPECT_GT(resampler.resample(near_view, r).cells_marked, 0u);
  for (int level = 1; level < resampler.mip_levels(); ++level) {
    r.mip = level;
    const ResampleResult coarse = resampler.resample(near_view, r);
    EXPECT_EQ(coarse.mip_level, level);
    // A coarse sample keeps the most frequent ids of its children: it still marks cells
    // (the odd counts' last samples included: no ray reads past the end).
    EXPECT_GT(coarse.cells_marked, 0u) << level;
  }
  // Far away, the automatic level is the deepest; a viewer at 1e300 must not overflow.
  r.mip = -1;
  for (const double distance : {1e4, 1e300}) {
    const ResampleResult far = resampler.resample(view_of(field, {0, 0, distance}, {0, 0, 0}, 40), r);
    EXPECT_EQ(far.mip_level, resampler.mip_levels() - 1) << distance;
  }
  // Looking away from the box, nothing is marked (the lines cross it behind the eye).
  r.mip = 0;
  const ResampleResult away = resampler.resample(view_of(field, {0, 0, 5}, {0, 0, 10}, 90), r);
  EXPECT_EQ(away.cells_marked, 0u);
  EXPECT_EQ(away.rays_in_field, 0u);
}

TEST(Field, SparseGroupNumbersBecomeDenseObjects) {
  const Mesh scene = wall_with_window_and_box();
  CellOptions groups;
  groups.grid = 2;
  groups.face_objects.assign(scene.num_faces(), 16777215u);
  for (std::size_t f = 0; f < 8; ++f) groups.face_objects[f] = 7;
  const CellPartition cells = partition_cells(scene, groups);
  EXPECT_EQ(cells.objects, 2u);
  for (const CellKey& k : cells.keys) EXPECT_LT(k.object, 2u);
}

TEST(Field, AViewerInsideTheBoxUsesTheLayerAheadAndMarksTheGap) {
  // Two spheres along x; the viewer stands between them looking at the +x one.
  Mesh scene;
  append(scene, test::icosphere(3), {-4, 0, 0});
  append(scene, test::icosphere(3), {4, 0, 0});
  FieldOptions options;
  options.cells.grid = 6;
  options.layers = 4;
  options.uv = options.st = 8;
  const VisibilityField field = build_field(scene, options);
  EXPECT_FALSE(field.inside_solid({0, 0, 0}));
  EXPECT_TRUE(field.inside_solid({4, 0, 0}));
  EXPECT_TRUE(field.inside_solid({-4.2, 0.1, 0.3}));
  const FieldResampler resampler(field);
  ResampleOptions r;
  r.subsample = 1;
  const ResampleResult result = resampler.resample(view_of(field, {0, 0, 0}, {4, 0, 0}, 40), r);
  const std::uint32_t ahead = field.cells.keys[field.cells.face_cell.back()].object;
  const std::uint32_t behind = field.cells.keys[field.cells.face_cell.front()].object;
  EXPECT_TRUE(any_marked(result.marked, field.cells, ahead));
  EXPECT_FALSE(any_marked(result.marked, field.cells, behind));
}

TEST(PerspectiveRaster, AgreesWithRayCastingPixelByPixel) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  std::vector<std::array<float, 3>> positions;
  for (const Vec3& p : bunny.positions) positions.push_back({float(p.x), float(p.y), float(p.z)});
  const RayCaster caster(positions, bunny.faces);
  const BoundingBox box = bounding_box(bunny);
  PerspectiveRasterizer raster;
  PerspectiveFrame frame;
  // Outside, close (triangles cross the near plane and leave the guard band) and inside.
  for (const double distance : {1.2, 0.3, 0.05}) {
    const Vec3 eye = box.center() + Vec3{0.3, 0.5, 1} * (distance * box.diagonal());
    const PerspectiveView view = PerspectiveView::looking_at(eye, box.center(), 70, 96, 1e-4 * box.diagonal());
    raster.draw(positions, bunny.faces, nullptr, view, frame);
    std::size_t agree = 0, covered = 0;
    for (int j = 0; j < view.resolution; ++j) {
      for (int i = 0; i < view.resolution; ++i) {
        const Vec3 d = view.pixel_ray(i, j);
        const std::uint32_t hit = caster.first_hit({float(eye.x), float(eye.y), float(eye.z)},
                                                   {float(d.x), float(d.y), float(d.z)}, float(view.near));
        const std::uint32_t id = frame.ids[static_cast<std::size_t>(j) * view.resolution + i];
        covered += hit != RayCaster::kNoHit;
        agree += (hit == RayCaster::kNoHit ? 0 : hit + 1) == id;
      }
    }
    EXPECT_GT(covered, 500u) << distance;
    // Ties on shared edges may go either way; anything else is a rasterizer error.
    EXPECT_GT(static_cast<double>(agree), 0.98 * view.resolution * view.resolution) << distance;
  }
}

}  // namespace
}  // namespace visimp
