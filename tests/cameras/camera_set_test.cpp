#include "visimp/cameras/camera_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"

namespace visimp {
namespace {

double angle(const Vec3& a, const Vec3& b) { return std::acos(std::clamp(dot(a, b), -1.0, 1.0)); }

// Smallest angle from each direction to any other.
std::vector<double> nearest_neighbour_angles(const std::vector<Vec3>& d) {
  std::vector<double> out(d.size(), 10.0);
  for (std::size_t i = 0; i < d.size(); ++i)
    for (std::size_t j = 0; j < d.size(); ++j)
      if (i != j) out[i] = std::min(out[i], angle(d[i], d[j]));
  return out;
}

TEST(OctahedronCameras, CountsAreThePapersSix) {
  const std::size_t expected[] = {6, 18, 66, 258, 1026, 4098};  // Zhang & Turk 2002, §4
  for (int level = 0; level <= 5; ++level) {
    const CameraSet set = octahedron_cameras(level);
    EXPECT_EQ(set.size(), expected[level]);
    EXPECT_EQ(octahedron_camera_count(level), expected[level]);
    for (const Vec3& d : set.directions) EXPECT_NEAR(norm(d), 1.0, 1e-12);
  }
  EXPECT_THROW(octahedron_cameras(6), UsageError);
}

TEST(OctahedronCameras, AreEvenlySpacedAndDistinct) {
  for (int level = 1; level <= 4; ++level) {
    const std::vector<double> nn = nearest_neighbour_angles(octahedron_cameras(level).directions);
    const auto [lo, hi] = std::minmax_element(nn.begin(), nn.end());
    EXPECT_GT(*lo, 0.0);
    // Projected midpoint subdivision is not perfectly even; spacing stays within a factor 1.6.
    EXPECT_LT(*hi / *lo, 1.6) << "level " << level;
  }
}

TEST(SphereTessellation, LocateAgreesWithBruteForce) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  for (int level = 0; level <= 5; ++level) {
    const SphereTessellation t(level);
    EXPECT_EQ(t.leaf_faces().size(), std::size_t{8} << (2 * level));
    for (int i = 0; i < 3000; ++i) {
      const Vec3 p{gauss(rng), gauss(rng), gauss(rng)};
      const std::uint32_t face = t.locate(p);
      ASSERT_LT(face, t.leaf_faces().size());
      ASSERT_TRUE(t.contains(face, p)) << "level " << level;
      // Brute force finds the same face unless p sits on a border it shares.
      std::size_t containing = 0;
      for (std::uint32_t f = 0; f < t.leaf_faces().size(); ++f) containing += t.contains(f, p) ? 1 : 0;
      ASSERT_GE(containing, 1u);
    }
    // Every camera direction is a vertex of the face it is located in.
    for (VertexIndex v = 0; v < t.vertices().size(); ++v) {
      const Face& f = t.leaf_faces()[t.locate(t.vertices()[v])];
      EXPECT_TRUE(f[0] == v || f[1] == v || f[2] == v);
    }
  }
}

TEST(DodecahedronCameras, TwentyVerticesThreeEqualNeighbours) {
  const CameraSet set = dodecahedron_cameras();
  ASSERT_EQ(set.size(), 20u);
  const double edge = nearest_neighbour_angles(set.directions)[0];
  for (const Vec3& a : set.directions) {
    int neighbours = 0;
    for (const Vec3& b : set.directions) neighbours += std::abs(angle(a, b) - edge) < 1e-9 ? 1 : 0;
    EXPECT_EQ(neighbours, 3);
  }
}

TEST(CameraFile, ReadsNormalisesAndRejectsBadLines) {
  const test::TempDir temp("camera_file");
  const std::string& dir = temp.path();
  { std::ofstream(dir + "/good.txt") << "# two cameras\n0 0 2\n\n1 1 0  # diagonal\n"; }
  const CameraSet set = read_camera_file(dir + "/good.txt");
  ASSERT_EQ(set.size(), 2u);
  EXPECT_EQ(set.directions[0], Vec3(0, 0, 1));
  EXPECT_NEAR(set.directions[1].x, std::sqrt(0.5), 1e-15);
  { std::ofstream(dir + "/bad.txt") << "0 0 1\n0 0\n"; }
  try {
    read_camera_file(dir + "/bad.txt");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt: line 2"), std::string::npos) << e.what();
  }
  { std::ofstream(dir + "/zero.txt") << "0 0 0\n"; }
  EXPECT_THROW(read_camera_file(dir + "/zero.txt"), IoError);
  EXPECT_THROW(read_camera_file(dir + "/missing.txt"), IoError);
  EXPECT_EQ(camera_set_from_spec("258").size(), 258u);
  EXPECT_EQ(camera_set_from_spec("k2").size(), 66u);
  EXPECT_EQ(camera_set_from_spec("dodecahedron").size(), 20u);
  EXPECT_THROW(camera_set_from_spec("100"), UsageError);
}

}  // namespace
}  // namespace visimp
