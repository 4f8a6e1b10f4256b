#include "visimp/metrics/surface_distance.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

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

}  // namespace
}  // namespace visimp
