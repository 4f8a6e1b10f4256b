#include "visimp/core/orientation.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

namespace visimp {
namespace {

// The canonical faces of a mesh: what visibility renders.
std::vector<Face> canonical_faces(const Mesh& m) {
  const OrientationPatches p = orientation_patches(m);
  std::vector<Face> out;
  for (std::size_t f = 0; f < m.num_faces(); ++f) out.push_back(canonical_face(m.faces[f], p.reversed[f] != 0));
  return out;
}

Mesh reversed_where(Mesh m, const std::vector<bool>& flip) {
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    if (flip[f]) std::swap(m.faces[f][0], m.faces[f][2]);  // a reversal that also rotates
  }
  return m;
}

// The edge matching on several threads, and a patch's volume summed in runs, give the same
// patches, windings and volumes as one thread: two spheres larger than one run (one
// randomly flipped face by face), and an open sheet.
TEST(Orientation, SamePatchesForAnyThreadCount) {
  Mesh m = test::icosphere(6);  // 81,920 faces
  std::vector<bool> flip(m.num_faces());
  for (std::size_t f = 0; f < flip.size(); ++f) flip[f] = (f * 2654435761u) % 7 < 3;
  m = reversed_where(m, flip);
  for (const Mesh& part : {test::icosphere(5, 0.5), test::grid(40)}) {
    const auto offset = static_cast<VertexIndex>(m.positions.size());
    for (const Vec3& p : part.positions) m.positions.push_back(p + Vec3{3, 0, 0});
    for (const Face& f : part.faces) m.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  }
  const OrientationPatches one = orientation_patches(m, 1), three = orientation_patches(m, 3);
  ASSERT_EQ(one.patches(), 3u);
  EXPECT_EQ(one.closed, (std::vector<std::uint8_t>{1, 1, 0}));
  EXPECT_EQ(one.patch_of_face, three.patch_of_face);
  EXPECT_EQ(one.reversed, three.reversed);
  EXPECT_EQ(one.closed, three.closed);
  EXPECT_EQ(one.signed_volume, three.signed_volume);
  EXPECT_NEAR(one.signed_volume[0], 4.18879, 0.01);  // 4π/3, the unit sphere's
}

TEST(Orientation, CanonicalFaceIgnoresRotationAndKeepsTheSide) {
  EXPECT_EQ(canonical_face({4, 2, 7}, false), (Face{2, 7, 4}));
  EXPECT_EQ(canonical_face({7, 4, 2}, false), (Face{2, 7, 4}));
  EXPECT_EQ(canonical_face({4, 7, 2}, true), (Face{2, 7, 4}));  // the other side, reversed back
  EXPECT_EQ(canonical_face({4, 7, 2}, false), (Face{2, 4, 7}));
}

TEST(Orientation, AClosedSurfaceIsWoundOutwardWhateverFacesAreReversed) {
  const Mesh cube = test::subdivided_cube(3);  // outward, volume 1
  const std::vector<Face> expected = canonical_faces(cube);
  for (std::size_t f = 0; f < cube.num_faces(); ++f) EXPECT_EQ(expected[f], canonical_face(cube.faces[f], false));
  for (int pattern = 0; pattern < 4; ++pattern) {
    std::vector<bool> flip(cube.num_faces());
    for (std::size_t f = 0; f < flip.size(); ++f)
      flip[f] = pattern == 1 || (pattern == 2 && f % 2 == 0) || (pattern == 3 && f % 7 < 3);
    const Mesh m = reversed_where(cube, flip);
    const OrientationPatches p = orientation_patches(m);
    ASSERT_EQ(p.patches(), 1u);
    EXPECT_TRUE(p.closed[0]);
    EXPECT_NEAR(p.signed_volume[0], 1.0, 1e-12);
    EXPECT_EQ(canonical_faces(m), expected) << "pattern " << pattern;
    for (std::size_t f = 0; f < flip.size(); ++f) EXPECT_EQ(p.reversed[f] != 0, flip[f]);
  }
}

TEST(Orientation, OpenNonManifoldAndNonOrientableSurfacesAreNotClosed) {
  // An open grid: one patch, not closed; a reversed face is wound back like its neighbours.
  Mesh grid = test::grid(2);
  std::swap(grid.faces[3][1], grid.faces[3][2]);
  OrientationPatches p = orientation_patches(grid);
  ASSERT_EQ(p.patches(), 1u);
  EXPECT_FALSE(p.closed[0]);
  for (std::size_t f = 0; f < grid.num_faces(); ++f)
    EXPECT_EQ(p.reversed[f] != 0, f == 3 ? !p.reversed[0] : p.reversed[0] != 0);

  // A cube with a third face on one edge: that edge joins no patch, so none is closed.
  Mesh fin = test::subdivided_cube(1);
  fin.positions.push_back({0.5, -1, 0});
  fin.faces.push_back({fin.faces[0][0], fin.faces[0][1], 8});
  p = orientation_patches(fin);
  for (std::size_t k = 0; k < p.patches(); ++k) EXPECT_FALSE(p.closed[k]);

  // A Möbius band of 8 quads: every edge has two faces but no consistent winding exists.
  Mesh band;
  const int n = 8;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * 3.14159265358979 * i / n, t = a / 2;
    for (int s : {-1, 1}) {
      band.positions.push_back({(2 + 0.5 * s * std::cos(t)) * std::cos(a), (2 + 0.5 * s * std::cos(t)) * std::sin(a),
                                0.5 * s * std::sin(t)});
    }
  }
  for (int i = 0; i < n; ++i) {
    const VertexIndex a0 = 2 * i, a1 = 2 * i + 1;
    const VertexIndex b0 = i + 1 < n ? 2 * (i + 1) : 1, b1 = i + 1 < n ? 2 * (i + 1) + 1 : 0;  // the half twist
    band.faces.push_back({a0, b0, a1});
    band.faces.push_back({a1, b0, b1});
  }
  p = orientation_patches(band);
  ASSERT_EQ(p.patches(), 1u);
  EXPECT_FALSE(p.closed[0]);

  // Two faces glued back to back close every edge but enclose nothing.
  Mesh sheet = test::grid(1);
  const std::size_t faces = sheet.num_faces();
  for (std::size_t f = 0; f < faces; ++f)
    sheet.faces.push_back({sheet.faces[f][0], sheet.faces[f][2], sheet.faces[f][1]});
  p = orientation_patches(sheet);
  for (std::size_t k = 0; k < p.patches(); ++k) EXPECT_FALSE(p.closed[k]);
}

TEST(Orientation, EachComponentIsItsOwnPatch) {
  Mesh two = test::subdivided_cube(2);
  const Mesh sphere = test::icosphere(2);
  const auto offset = static_cast<VertexIndex>(two.num_vertices());
  for (const Vec3& q : sphere.positions) two.positions.push_back(q + Vec3{5, 0, 0});
  for (const Face& f : sphere.faces) two.faces.push_back({f[0] + offset, f[2] + offset, f[1] + offset});  // inward
  const OrientationPatches p = orientation_patches(two);
  ASSERT_EQ(p.patches(), 2u);
  EXPECT_TRUE(p.closed[0] && p.closed[1]);
  for (std::size_t f = 0; f < two.num_faces(); ++f) {
    EXPECT_EQ(p.patch_of_face[f], f < 24 * 2 ? 0u : 1u);
    EXPECT_EQ(p.reversed[f] != 0, f >= 48);  // only the inward sphere is turned
  }
}

}  // namespace
}  // namespace visimp
