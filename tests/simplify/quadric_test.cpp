#include "visimp/simplify/quadric.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <utility>

namespace visimp {
namespace {

TEST(Quadric, PlaneMeasuresWeightedSquaredDistance) {
  const Quadric q = Quadric::plane({0, 0, 1}, {0, 0, 2}, 3.0);  // 3·(z - 2)²
  EXPECT_DOUBLE_EQ(q.evaluate({5, -1, 4}), 12.0);
  EXPECT_DOUBLE_EQ(q.evaluate({1, 1, 2}), 0.0);
  EXPECT_DOUBLE_EQ(q.area, 3.0);
}

std::uint64_t bits_of(double d) {
  std::uint64_t b;
  std::memcpy(&b, &d, sizeof b);
  return b;
}

// VG's cost quadrics are stored in evaluation's pairs and evaluated two lanes at a time on
// x86: sums and values must keep the plain layout's bits, or VG with V = 1 would stop
// reproducing QB's collapse order (VisibilityGuided.WithVisibilityOneEverywhereItIsQbBitForBit; the benchmark's
// overhead rows rely on it).
TEST(CostQuadric, SumsAndValuesHaveThePlainLayoutsBits) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40);
  const auto any = [&] { return std::ldexp(unit(random), exponent(random)); };
  const auto direction = [&] {
    const Vec3 n{unit(random), unit(random), unit(random)};
    return n / norm(n);
  };
  int positive = 0;
  for (int i = 0; i < 20000; ++i) {
    Quadric q, r;
    if (i % 2 == 0) {  // sums of weighted planes, as the engine builds them
      for (int k = 0; k < 3; ++k) {
        q += Quadric::plane(direction(), {any(), any(), any()}, std::abs(any()));
        r += Quadric::plane(direction(), {any(), any(), any()}, std::abs(any()));
      }
    } else {  // arbitrary coefficients: every lane must match, not only PSD cases
      for (Quadric* t : {&q, &r}) *t = Quadric{any(), any(), any(), any(), any(), any(), any(), any(), any(), any(), 0};
    }
    const Vec3 p{any(), any(), any()};
    const CostQuadric cq = CostQuadric::from(q), cr = CostQuadric::from(r);
    const double value = CostQuadric::evaluate_sum(cq, cr, p);
    ASSERT_EQ(bits_of(value), bits_of((q + r).evaluate(p))) << "case " << i;
    alignas(16) const CostQuadric aligned_q = cq, aligned_r = cr;  // as the engine's records hold them
    ASSERT_EQ(bits_of(CostQuadric::evaluate_aligned_sum(aligned_q, aligned_r, p)), bits_of(value)) << "case " << i;
    // A merged vertex's cost quadric (+=) evaluates as the plain sum does.
    CostQuadric merged = cq;
    merged += cr;
    ASSERT_EQ(bits_of(CostQuadric::evaluate_sum(merged, CostQuadric{}, p)), bits_of((q + r).evaluate(p))) << "case " << i;
    positive += value > 0;
  }
  EXPECT_GT(positive, 10000);  // the clamp at 0 did not make the comparison trivial
}

// place() evaluates both endpoints in one packed pass: each lane must be evaluate()'s bits, or
// the choice between endpoints (and every output mesh) would change with the target's SIMD.
TEST(Quadric, EvaluatePairHasEvaluatesBitsInBothLanes) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-40, 40);
  const auto any = [&] { return std::ldexp(unit(random), exponent(random)); };
  int positive = 0, zero = 0;
  for (int i = 0; i < 20000; ++i) {
    Quadric q;
    if (i % 2 == 0) {
      for (int k = 0; k < 3; ++k) {
        const Vec3 n{unit(random), unit(random), unit(random)};
        q += Quadric::plane(n / norm(n), {any(), any(), any()}, std::abs(any()));
      }
    } else {  // arbitrary coefficients, negative values (clamped) and NaN included
      q = Quadric{any(), any(), any(), any(), any(), any(), any(), any(), any(), any(), 0};
      if (i % 1000 == 1) q.c = std::nan("");
    }
    const Vec3 p{any(), any(), any()}, r{any(), any(), any()};
    double qp = -1, qr = -1;
    q.evaluate_pair(p, r, qp, qr);
    ASSERT_EQ(bits_of(qp), bits_of(q.evaluate(p))) << "case " << i;
    ASSERT_EQ(bits_of(qr), bits_of(q.evaluate(r))) << "case " << i;
    positive += qp > 0;
    zero += qr == 0;
  }
  EXPECT_GT(positive, 10000);  // neither the clamp nor the comparison is trivial
  EXPECT_GT(zero, 1000);
}

TEST(Quadric, ThreePlanesPlaceAtTheirCorner) {
  Quadric q = Quadric::plane({1, 0, 0}, {1, 0, 0}, 1) + Quadric::plane({0, 1, 0}, {0, 2, 0}, 1) +
              Quadric::plane({0, 0, 1}, {0, 0, 3}, 1);
  const Placement p = place(q, {0.9, 1.9, 2.9}, {1.2, 2.1, 3.2});
  EXPECT_EQ(p.kind, PlacementKind::optimal);
  EXPECT_NEAR(p.position.x, 1, 1e-12);
  EXPECT_NEAR(p.position.y, 2, 1e-12);
  EXPECT_NEAR(p.position.z, 3, 1e-12);
}

TEST(Quadric, SinglePlaneIsSingularAndKeepsAnEndpoint) {
  // A flat region: A has rank 1. Both endpoints lie on the plane, so either is optimal and the
  // placement keeps one exactly instead of inventing a point.
  const Quadric q = Quadric::plane({0, 0, 1}, {0, 0, 0}, 1);
  const Placement p = place(q, {0, 0, 0}, {1, 0, 0});
  EXPECT_EQ(p.kind, PlacementKind::endpoint0);
  EXPECT_EQ(p.position, (Vec3{0, 0, 0}));
}

TEST(Quadric, NearlySingularPlacementStaysNearTheEdge) {
  // Two planes 1e-7 rad apart: the exact minimiser of A x = -b lies ~1e6 away along their
  // near-common line. The rank-revealing solve must not go there.
  const double e = 1e-7;
  const Quadric q =
      Quadric::plane({0, 0, 1}, {0, 0, 0.01}, 1) + Quadric::plane({0, std::sin(e), std::cos(e)}, {0, 0, 0}, 1);
  const Placement p = place(q, {0, 0, 0}, {0, 1, 0});
  EXPECT_LT(norm(p.position - Vec3{0, 0.5, 0}), 2.0);
  EXPECT_TRUE(is_finite(p.position));
}

TEST(Quadric, CreaseIsSolvedAcrossAndKeepsTheMidpointAlong) {
  // Planes x = 1 and y = 2 meet in a line along z: A has rank 2. The point goes onto the line
  // (up to the damping, 1e-3 of the way) and keeps the midpoint's z exactly.
  const Quadric q = Quadric::plane({1, 0, 0}, {1, 0, 0}, 1) + Quadric::plane({0, 1, 0}, {0, 2, 0}, 1);
  const Placement p = place(q, {0, 0, 0.3}, {1, 1, 0.7});
  EXPECT_EQ(p.kind, PlacementKind::pseudo_inverse);
  EXPECT_NEAR(p.position.x, 1.0, 2e-3);
  EXPECT_NEAR(p.position.y, 2.0, 4e-3);
  EXPECT_EQ(p.position.z, 0.5);
  EXPECT_LT(p.error, 1e-5);
}

TEST(Quadric, EmptyQuadricKeepsAnEndpoint) {
  const Placement p = place(Quadric{}, {1, 2, 3}, {4, 5, 6});
  EXPECT_EQ(p.position, (Vec3{1, 2, 3}));
}

TEST(Quadric, FarAwayOptimumFallsBackToTheSegment) {
  // Three planes meeting at (100, 0, 0), edge near the origin: the optimum is 100 edge lengths away.
  const Quadric q = Quadric::plane({1, 0, 0}, {100, 0, 0}, 1) + Quadric::plane({0, 1, 0}, {0, 0, 0}, 1) +
                    Quadric::plane({0, 0, 1}, {0, 0, 0}, 1);
  const Placement p = place(q, {0, 0, 0}, {1, 0, 0});
  EXPECT_EQ(p.kind, PlacementKind::endpoint1);  // the segment's best point is its end at x = 1
}

// The collapse loop takes the error from the placement instead of evaluating Q again: it must
// be Q at the returned point, bit for bit, whichever branch chose the point.
TEST(Quadric, PlacementCarriesTheErrorAtItsPoint) {
  const Quadric corner = Quadric::plane({1, 0, 0}, {1, 0, 0}, 1) + Quadric::plane({0, 1, 0}, {0, 2, 0}, 2) +
                         Quadric::plane({0, 0.6, 0.8}, {0, 0, 3}, 0.5) + Quadric::plane({0.6, 0, 0.8}, {0, 0, 5}, 1);
  const Quadric flat = Quadric::plane({0, 0, 1}, {0, 0, 0.25}, 1) + Quadric::plane({0, 0, 1}, {0, 0, 0.35}, 1);
  const Quadric far = Quadric::plane({1, 0, 0}, {100, 0, 0}, 1) + Quadric::plane({0, 1, 0}, {0, 0, 0}, 100) +
                      Quadric::plane({0, 0, 1}, {0, 0, 0}, 1);
  const std::pair<Quadric, PlacementKind> cases[] = {
      {corner, PlacementKind::optimal}, {flat, PlacementKind::pseudo_inverse}, {far, PlacementKind::segment}};
  for (const auto& [q, kind] : cases) {
    const Placement p = place(q, {0, -1, 0.1}, {1, 1, 0.2});
    EXPECT_EQ(p.kind, kind);
    EXPECT_GT(p.error, 0.0);
    EXPECT_EQ(p.error, q.evaluate(p.position));
  }
  const Placement endpoint = place(flat, {0, 0, 0.3}, {1, 0, 0.2});
  EXPECT_EQ(endpoint.kind, PlacementKind::endpoint0);
  EXPECT_GT(endpoint.error, 0.0);
  EXPECT_EQ(endpoint.error, flat.evaluate(endpoint.position));
}

}  // namespace
}  // namespace visimp
