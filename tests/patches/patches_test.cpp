// Patches, bitfields, their file and view reconstruction on meshes with known answers.
#include <gtest/gtest.h>

#include <type_traits>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/cameras/camera_set.h"
#include "visimp/io/byte_stream.h"
#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"
#include "visimp/patches/bitfield_file.h"
#include "visimp/patches/bitfields.h"
#include "visimp/patches/patch_partition.h"
#include "visimp/patches/patch_study.h"
#include "visimp/patches/sample_selection.h"
#include "visimp/patches/view_reconstruction.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/bounding_box.h"
#include "visimp/visibility/visibility.h"

namespace visimp {
namespace {

// These keep references to their inputs: temporaries must not compile.
static_assert(!std::is_constructible_v<ViewReconstructor, BitfieldSet&&>);
static_assert(!std::is_constructible_v<BitfieldRecorder, Mesh&&, const RenderScene&, std::vector<std::uint32_t>,
                                       const PatchPartition&, std::size_t, const BitfieldOptions&>);
static_assert(!std::is_constructible_v<ByteReader, std::string, std::string&&, std::string>);

Mesh appended(Mesh a, const Mesh& b) {
  const auto offset = static_cast<VertexIndex>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (Face f : b.faces) a.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  return a;
}

Mesh translated(Mesh m, const Vec3& t) {
  for (Vec3& p : m.positions) p += t;
  return m;
}

// The unit cube [0,1]^3 (closed) sealing a sphere of radius 0.3 at its centre.
struct Sealed {
  Mesh mesh;
  std::size_t box_faces = 0;
};
Sealed sphere_sealed_in_box() {
  Sealed s;
  s.mesh = test::subdivided_cube(4);
  s.box_faces = s.mesh.num_faces();
  s.mesh = appended(s.mesh, translated(test::icosphere(3, 0.3), {0.5, 0.5, 0.5}));
  return s;
}

// Each patch's faces form one edge-connected piece.
bool patches_connected(const Mesh& mesh, const PatchPartition& p) {
  const auto neighbours = face_neighbours(mesh);
  std::vector<bool> reached(mesh.num_faces(), false);
  std::vector<bool> patch_started(p.patch_count(), false);
  for (std::uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (reached[f]) continue;
    if (patch_started[p.face_patch[f]]) return false;  // a second piece of a patch
    patch_started[p.face_patch[f]] = true;
    std::vector<std::uint32_t> stack{f};
    reached[f] = true;
    while (!stack.empty()) {
      const std::uint32_t g = stack.back();
      stack.pop_back();
      for (std::uint32_t h : neighbours[g]) {
        if (!reached[h] && p.face_patch[h] == p.face_patch[g]) {
          reached[h] = true;
          stack.push_back(h);
        }
      }
    }
  }
  return true;
}

BitfieldSet make_set(const Mesh& mesh, const PatchPartition& partition, bool per_face, const CameraSet& cameras,
                     const BitfieldOptions& options = {}, int resolution = 128) {
  RenderOptions render;
  render.resolution = resolution;
  auto renderer = make_raster_renderer(render);
  BitfieldSet set = make_bitfield_set(mesh, partition, per_face, cameras, resolution, options);
  set.bits = record_bitfields(mesh, partition, cameras, *renderer, options);
  return set;
}

TEST(Patches, CountIsExactEveryFaceHasOneConnectedPatch) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  for (std::size_t count : {1u, 37u, 500u}) {
    PatchOptions options;
    options.count = count;
    const PatchPartition p = build_patches(bunny, options);
    ASSERT_EQ(p.patch_count(), std::max<std::size_t>(count, p.components)) << count;
    ASSERT_EQ(p.face_patch.size(), bunny.num_faces());
    std::size_t faces = 0;
    for (std::uint32_t n : p.face_count) faces += n;
    EXPECT_EQ(faces, bunny.num_faces());
    for (std::uint32_t q : p.face_patch) ASSERT_LT(q, p.patch_count());
    EXPECT_TRUE(patches_connected(bunny, p)) << count;
    // Deterministic.
    EXPECT_EQ(build_patches(bunny, options).face_patch, p.face_patch);
  }
}

TEST(Patches, SeveralComponentsAndNonManifoldEdges) {
  // Two spheres apart: never fused across, so asking for 1 patch gives 2.
  Mesh two = appended(test::icosphere(2), translated(test::icosphere(2), {5, 0, 0}));
  PatchOptions options;
  options.count = 1;
  PatchPartition p = build_patches(two, options);
  EXPECT_EQ(p.components, 2u);
  EXPECT_EQ(p.patch_count(), 2u);
  options.count = 12;
  p = build_patches(two, options);
  EXPECT_EQ(p.patch_count(), 12u);
  EXPECT_TRUE(patches_connected(two, p));

  // A fan of four triangles around one edge (non-manifold), plus a degenerate face.
  Mesh fan;
  fan.positions = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  fan.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}, {1, 0, 5}, {2, 2, 4}};
  options.count = 1;
  p = build_patches(fan, options);
  EXPECT_EQ(p.components, 2u);  // the repeated-index face shares no edge
  EXPECT_EQ(p.patch_count(), 2u);
  EXPECT_TRUE(patches_connected(fan, p));
}

TEST(Patches, DiagonalLimitHolds) {
  const Mesh sphere = test::icosphere(4);
  PatchOptions options;
  options.count = 0;
  options.max_diagonal = 0.6;
  const PatchPartition p = build_patches(sphere, options);
  EXPECT_GT(p.patch_count(), 10u);
  EXPECT_LT(p.patch_count(), sphere.num_faces() / 4);
  for (double d : p.diagonal) EXPECT_LE(d, 0.6);
  EXPECT_TRUE(patches_connected(sphere, p));
  options.max_diagonal = 0;
  EXPECT_THROW(check_options(options), UsageError);
}

TEST(SampleSelection, HierarchyAgreesWithBruteForce) {
  for (int level : {0, 2, 4}) {
    const CameraSet cameras = octahedron_cameras(level);
    const SampleSelector selector(cameras);
    ASSERT_TRUE(selector.hierarchical());
    const SphereTessellation tessellation(level);
    for (const Vec3& d : random_directions(2000, 7 + static_cast<std::uint64_t>(level))) {
      const std::uint32_t cell = selector.cell(d);
      ASSERT_TRUE(tessellation.contains(cell, d));
      // Brute force: the one leaf face holding d (random directions are never on an edge).
      std::size_t holding = 0;
      for (std::uint32_t f = 0; f < tessellation.leaf_faces().size(); ++f) holding += tessellation.contains(f, d);
      ASSERT_EQ(holding, 1u);
      EXPECT_EQ(selector.select(d).count, 3u);
    }
  }
}

TEST(SampleSelection, ConvexHullOfArbitrarySetsFindsTheSurroundingFace) {
  CameraSet cameras{"random-300", random_directions(300, 99)};
  const SampleSelector selector(cameras);
  ASSERT_FALSE(selector.hierarchical());
  EXPECT_EQ(selector.cells(), 2 * 300u - 4);  // a triangulated sphere: F = 2V − 4
  std::size_t six = 0;
  for (const Vec3& d : random_directions(3000, 5)) {
    const auto c = selector.corners(selector.cell(d));
    const Vec3 &a = cameras.directions[c[0]], &b = cameras.directions[c[1]], &e = cameras.directions[c[2]];
    ASSERT_GE(dot(cross(a, b), d), 0);
    ASSERT_GE(dot(cross(b, e), d), 0);
    ASSERT_GE(dot(cross(e, a), d), 0);
    // 3 corners + the far corner of each edge-neighbour; two neighbours share it only
    // around a corner of valence 3.
    const SampleChoice choice = selector.select(d);
    ASSERT_GE(choice.count, 4u);
    ASSERT_LE(choice.count, 6u);
    const std::set<std::uint32_t> distinct(choice.samples.begin(),
                                           choice.samples.begin() + static_cast<std::ptrdiff_t>(choice.count));
    EXPECT_EQ(distinct.size(), choice.count);
    six += choice.count == 6;
  }
  EXPECT_GT(six, 2500u);
  // The dodecahedron's 20 directions work too; a half-space set does not.
  EXPECT_EQ(SampleSelector(dodecahedron_cameras()).cells(), 36u);
  CameraSet half{"half", {}};
  for (const Vec3& d : random_directions(50, 3)) half.directions.push_back({d.x, d.y, std::fabs(d.z) + 0.01});
  for (Vec3& d : half.directions) d = d / norm(d);
  EXPECT_THROW(SampleSelector{half}, UsageError);
}

TEST(Reconstruction, ASampleDirectionGetsEverythingThatSampleSaw) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  PatchOptions options;
  options.count = 200;
  const PatchPartition patches = build_patches(bunny, options);
  for (const CameraSet& cameras : {octahedron_cameras(3), dodecahedron_cameras()}) {
    const BitfieldSet set = make_set(bunny, patches, false, cameras);
    const ViewReconstructor reconstructor(set);
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      const std::vector<std::uint32_t> units = reconstructor.units(cameras.directions[c]);
      for (std::size_t u = 0; u < set.bits.units; ++u) {
        if (set.bits.test(c, u)) {
          ASSERT_TRUE(std::binary_search(units.begin(), units.end(), u)) << cameras.name << c;
        }
      }
    }
    // Precomputed cells answer the same.
    const ViewReconstructor precomputed(set, true);
    for (const Vec3& d : random_directions(200, 4)) EXPECT_EQ(precomputed.units(d), reconstructor.units(d));
  }
}

TEST(Reconstruction, ConvexMeshMissesNoPixelAt258Samples) {
  const Mesh sphere = test::icosphere(4);
  RenderOptions render;
  render.resolution = 256;
  auto renderer = make_raster_renderer(render);
  PatchStudyOptions options;
  options.patch_counts = {20, 300};
  options.max_level = 3;  // 258 cameras
  options.viewpoints = 200;
  options.pixel_views = 30;
  const PatchStudy study = run_patch_study(sphere, *renderer, nullptr, options);
  ASSERT_EQ(study.pixels.size(), 3u);
  for (const PixelCheck& check : study.pixels) {
    if (check.unit == "patches") {
      EXPECT_EQ(check.differing_pixels, 0u) << check.patches << " patches";
    }
    EXPECT_GT(check.mesh_pixels, 30u * 10000u);
  }
  // Culling grows with samples (a sphere: about half the faces face away).
  double previous = -1;
  for (const CullingPoint& c : study.culling) {
    if (c.unit != "faces") continue;
    EXPECT_GE(c.culling_rate, previous - 1e-12);
    previous = c.culling_rate;
  }
  EXPECT_GT(previous, 0.3);
  EXPECT_LT(previous, 0.5);
}

TEST(Reconstruction, ASealedObjectIsNeverDrawn) {
  const Sealed s = sphere_sealed_in_box();
  PatchOptions options;
  options.count = 60;
  const PatchPartition patches = build_patches(s.mesh, options);
  const PatchPartition faces = faces_as_patches(s.mesh);
  const CameraSet cameras = octahedron_cameras(2);
  for (bool per_face : {false, true}) {
    const BitfieldSet set = make_set(s.mesh, per_face ? faces : patches, per_face, cameras);
    const ViewReconstructor reconstructor(set);
    for (const Vec3& d : random_directions(300, 11)) {
      const std::vector<std::uint32_t> drawn = reconstructor.faces(d);
      ASSERT_FALSE(drawn.empty());
      EXPECT_LT(drawn.back(), s.box_faces) << "a sphere face was drawn";
    }
  }
}

TEST(Bitfields, TransparentFacesAreAlwaysSetAndHideNothing) {
  const Sealed s = sphere_sealed_in_box();
  BitfieldOptions options;
  options.transparent.assign(s.mesh.num_faces(), 0);
  std::fill(options.transparent.begin(), options.transparent.begin() + static_cast<std::ptrdiff_t>(s.box_faces), 1);
  const BitfieldSet set = make_set(s.mesh, faces_as_patches(s.mesh), true, octahedron_cameras(1), options);
  for (std::size_t c = 0; c < set.bits.cameras; ++c) {
    for (std::size_t f = 0; f < s.box_faces; ++f) ASSERT_TRUE(set.bits.test(c, f));
    std::size_t sphere_seen = 0;
    for (std::size_t f = s.box_faces; f < s.mesh.num_faces(); ++f) sphere_seen += set.bits.test(c, f);
    EXPECT_GT(sphere_seen, 100u);  // the glass box no longer hides the sphere
  }
}

TEST(Bitfields, NeighbourFillAddsFrontFacingNeighboursOnly) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  const PatchPartition faces = faces_as_patches(bunny);
  BitfieldOptions fill;
  fill.neighbour_fill = true;
  const CameraSet cameras = octahedron_cameras(1);
  const BitfieldSet plain = make_set(bunny, faces, true, cameras, {}, 48);
  const BitfieldSet filled = make_set(bunny, faces, true, cameras, fill, 48);
  std::size_t added = 0;
  for (std::size_t c = 0; c < cameras.size(); ++c) {
    for (std::size_t f = 0; f < bunny.num_faces(); ++f) {
      if (plain.bits.test(c, f)) {
        ASSERT_TRUE(filled.bits.test(c, f));
      } else if (filled.bits.test(c, f)) {
        ++added;
        EXPECT_GT(dot(face_normal_unnormalized(bunny, bunny.faces[f]), cameras.directions[c]), 0);
      }
    }
  }
  EXPECT_GT(added, 100u);  // at 48 pixels most bunny faces own no pixel
}

TEST(Bitfields, PatchBitsFromFaceBitsEqualRenderingThePatches) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  PatchOptions options;
  options.count = 100;
  const PatchPartition patches = build_patches(bunny, options);
  const CameraSet cameras = octahedron_cameras(2);
  const BitfieldSet direct = make_set(bunny, patches, false, cameras);
  const BitfieldSet faces = make_set(bunny, faces_as_patches(bunny), true, cameras);
  EXPECT_TRUE(patch_bitfields_from_faces(faces.bits, patches) == direct.bits);
}

TEST(Bitfields, RecordedInTheVisibilityPass) {
  const Mesh sphere = test::icosphere(3);
  const PatchPartition faces = faces_as_patches(sphere);
  const CameraSet cameras = octahedron_cameras(2);
  RenderOptions render;
  render.resolution = 128;
  auto renderer = make_raster_renderer(render);
  VisibilityOptions visibility;
  visibility.refine = false;
  const VisibilityJob job(sphere, render.resolution, visibility);
  BitfieldRecorder recorder(sphere, job.scene(), job.scene_input_faces(), faces, cameras.size(), {});
  const VisibilityTally with = job.render(cameras, 0, cameras.size(), *renderer, nullptr, &recorder);
  const VisibilityTally without = job.render(cameras, 0, cameras.size(), *renderer);
  EXPECT_EQ(with.seen, without.seen);
  const Bitfields shared = recorder.finish();
  const BitfieldSet alone = make_set(sphere, faces, true, cameras);
  EXPECT_TRUE(shared == alone.bits);
}

TEST(BitfieldFile, RoundTripsAndRejectsAnotherMesh) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  PatchOptions options;
  options.count = 50;
  const PatchPartition patches = build_patches(bunny, options);
  const BitfieldSet set = make_set(bunny, patches, false, octahedron_cameras(2));
  const test::TempDir temp("vbf");
  const std::string& dir = temp.path();
  for (bool compress : {false, true}) {
    const std::string path = dir + (compress ? "/c.vbf" : "/r.vbf");
    const BitfieldFileSizes sizes = write_bitfield_file(set, path, compress);
    EXPECT_EQ(sizes.total, std::filesystem::file_size(path));
    EXPECT_LE(sizes.bitfields, sizes.bitfields_uncompressed);
    const BitfieldSet back = read_bitfield_file(path);
    EXPECT_TRUE(back.bits == set.bits);
    EXPECT_EQ(back.face_patch, set.face_patch);
    EXPECT_EQ(back.cameras.name, set.cameras.name);
    EXPECT_EQ(back.cameras.directions.size(), set.cameras.directions.size());
    EXPECT_EQ(back.center.x, set.center.x);
    EXPECT_NO_THROW(check_bitfields_match(back, bunny, path));
    Mesh moved = bunny;
    moved.positions[0].x += 1e-6;
    EXPECT_THROW(check_bitfields_match(back, moved, path), IoError);
  }
  // Rows of a mesh with a hidden part are mostly zero words: coding them pays.
  const Sealed sealed = sphere_sealed_in_box();
  const BitfieldSet faces = make_set(sealed.mesh, faces_as_patches(sealed.mesh), true, octahedron_cameras(2));
  const BitfieldFileSizes coded = write_bitfield_file(faces, dir + "/faces.vbf", true);
  EXPECT_LT(coded.bitfields * 2, coded.bitfields_uncompressed);
  EXPECT_TRUE(read_bitfield_file(dir + "/faces.vbf").bits == faces.bits);

  // A flipped byte, a cut file and a foreign file are refused with the file's name.
  std::string bytes;
  {
    std::ifstream in(dir + "/c.vbf", std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  auto write = [&](const std::string& name, const std::string& content) {
    std::ofstream(dir + "/" + name, std::ios::binary) << content;
    return dir + "/" + name;
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  for (const std::string& path : {write("flipped.vbf", flipped), write("cut.vbf", bytes.substr(0, bytes.size() - 9)),
                                  write("other.vbf", "VISIMPT1 and more")}) {
    try {
      read_bitfield_file(path);
      ADD_FAILURE() << path << " was accepted";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(BitfieldFile, FaceListsNameTheLine) {
  const test::TempDir temp("facelist");
  const std::string& dir = temp.path();
  std::ofstream(dir + "/ok.txt") << "# glass\n0 2\n  5\n";
  const auto flags = read_face_list(dir + "/ok.txt", 6);
  EXPECT_EQ(flags, (std::vector<std::uint8_t>{1, 0, 1, 0, 0, 1}));
  std::ofstream(dir + "/bad.txt") << "1\n7\n";
  try {
    read_face_list(dir + "/bad.txt", 6);
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace visimp
