// Garland–Heckbert plane quadrics (Garland & Heckbert 1997; Zhang & Turk 2002 eq. 5.6–5.7)
// and the placement of the vertex an edge collapses to.
//
// A quadric is the symmetric 4×4 matrix [A b; bᵀ c] of a sum of weighted squared plane
// distances: Q(x) = xᵀAx + 2bᵀx + c = Σ w_i (n_i·x + d_i)². visimp builds quadrics in the
// unit frame (bounding-box centre at the origin, diagonal 1) so that their entries are O(1)
// whatever the input's position and scale.
#pragma once

#include <cstddef>

#include "visimp/core/vec3.h"

// The packed path needs SSE2 and no FMA: on an FMA target (-march=native, x86-64-v3) the
// compiler fuses evaluate_terms' scalar x·ax + y·ay, which two rounded lanes cannot reproduce.
#if defined(__SSE2__) && !defined(__FMA__)
#define VISIMP_PACKED_COST_QUADRIC 1
#include <emmintrin.h>
#endif

namespace visimp {

struct Quadric {
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;  // A (symmetric)
  double b0 = 0, b1 = 0, b2 = 0;                                // b
  double c = 0;
  /// Total face area this quadric was built from (constraint planes add none); turns a
  /// quadric error into a mean squared distance.
  double area = 0;

  /// weight · (n·x + d)² for the plane through `point` with unit normal `n`.
  static Quadric plane(const Vec3& n, const Vec3& point, double weight);

  Quadric& operator+=(const Quadric& o) {  // inline: the collapse loop's hottest operation
    a00 += o.a00;
    a01 += o.a01;
    a02 += o.a02;
    a11 += o.a11;
    a12 += o.a12;
    a22 += o.a22;
    b0 += o.b0;
    b1 += o.b1;
    b2 += o.b2;
    c += o.c;
    area += o.area;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }
  /// Scales every term (and the area): the VG weights V(t)².
  Quadric& operator*=(double s) {
    a00 *= s;
    a01 *= s;
    a02 *= s;
    a11 *= s;
    a12 *= s;
    a22 *= s;
    b0 *= s;
    b1 *= s;
    b2 *= s;
    c *= s;
    area *= s;
    return *this;
  }
  friend Quadric operator*(Quadric a, double s) { return a *= s; }

  /// Q(p), clamped at 0 (rounding can make it slightly negative).
  double evaluate(const Vec3& p) const { return evaluate_terms(a00, a01, a02, a11, a12, a22, b0, b1, b2, c, p); }

  /// {Q(p), Q(r)}: evaluate()'s bits for both (tests compare), the two in the lanes of one SSE2
  /// register where the target has it. place() asks for both endpoints of every edge it costs
  /// (~430k pairs for the D-sub at 1%): one pass of packed arithmetic instead of two scalar ones.
  void evaluate_pair(const Vec3& p, const Vec3& r, double& qp, double& qr) const;

  /// Q(p) from its coefficients, clamped at 0: the one definition of the arithmetic (and of its
  /// rounding), which CostQuadric's packed evaluation reproduces bit for bit.
  static double evaluate_terms(double a00, double a01, double a02, double a11, double a12, double a22, double b0,
                               double b1, double b2, double c, const Vec3& p) {
    const double ax = a00 * p.x + a01 * p.y + a02 * p.z;
    const double ay = a01 * p.x + a11 * p.y + a12 * p.z;
    const double az = a02 * p.x + a12 * p.y + a22 * p.z;
    const double e = p.x * ax + p.y * ay + p.z * az + 2 * (b0 * p.x + b1 * p.y + b2 * p.z) + c;
    return e > 0 ? e : 0.0;
  }
};

/// VG's cost quadric Q_v = Σ V(t)² K_t (Zhang & Turk eq. 5.7), kept for its one use: its value
/// at the point the plain quadric chose for a candidate collapse, at every queue push (~4M on
/// the dragon to 10%). The coefficients are stored in the pairs that evaluation multiplies by
/// the same coordinate — (a00 a01) (a01 a11) (a02 a12), times x, y, z, give the first two rows
/// of A·p; (a02 b0) (a12 b1) (a22 b2) its third row and b·p — so two SSE2 lanes compute two of
/// Quadric::evaluate_terms' dot products at once, in its order and with no shuffle: the bits are
/// the plain layout's (tests compare). Stored as a Quadric it took ~66 instructions a push, 4%
/// of a QB run's count; no `area`: nothing divides by it.
struct CostQuadric {
  double pairs[12] = {};
  double c = 0;

  /// q's coefficients in this layout.
  static CostQuadric from(const Quadric& q) {
    CostQuadric r;
    const double p[12] = {q.a00, q.a01, q.a01, q.a11, q.a02, q.a12, q.a02, q.b0, q.a12, q.b1, q.a22, q.b2};
    for (int i = 0; i < 12; ++i) r.pairs[i] = p[i];
    r.c = q.c;
    return r;
  }

  CostQuadric& operator+=(const CostQuadric& o) {  // every coefficient as Quadric::operator+= adds it
    for (int i = 0; i < 12; ++i) pairs[i] += o.pairs[i];
    c += o.c;
    return *this;
  }

  /// (q + r)(p) without storing the sum, clamped at 0: Quadric::evaluate's bits for the same sum.
  static double evaluate_sum(const CostQuadric& q, const CostQuadric& r, const Vec3& p) {
    return evaluate_sum_of<false>(q, r, p);
  }
  /// The same for two quadrics whose pairs start on 16-byte boundaries (the caller guarantees
  /// it, e.g. with an alignas(16) record): each pair's load then folds into its add, 6
  /// instructions fewer per evaluation (SSE2 arithmetic takes only aligned memory operands).
  static double evaluate_aligned_sum(const CostQuadric& q, const CostQuadric& r, const Vec3& p) {
    return evaluate_sum_of<true>(q, r, p);
  }

 private:
  template <bool kAligned>
  static double evaluate_sum_of(const CostQuadric& q, const CostQuadric& r, const Vec3& p) {
#if defined(VISIMP_PACKED_COST_QUADRIC)
    const auto load = [](const double* pair) { return kAligned ? _mm_load_pd(pair) : _mm_loadu_pd(pair); };
    const auto sum = [&](int pair) { return _mm_add_pd(load(q.pairs + 2 * pair), load(r.pairs + 2 * pair)); };
    const __m128d x = _mm_set1_pd(p.x), y = _mm_set1_pd(p.y), z = _mm_set1_pd(p.z);
    // Each lane is (α·x + β·y) + γ·z, as every dot product in evaluate_terms (no FMA target,
    // see VISIMP_PACKED_COST_QUADRIC: neither side is contracted).
    const __m128d ax_ay = _mm_add_pd(_mm_add_pd(_mm_mul_pd(sum(0), x), _mm_mul_pd(sum(1), y)), _mm_mul_pd(sum(2), z));
    const __m128d az_bp = _mm_add_pd(_mm_add_pd(_mm_mul_pd(sum(3), x), _mm_mul_pd(sum(4), y)), _mm_mul_pd(sum(5), z));
    const __m128d xax_yay = _mm_mul_pd(_mm_loadu_pd(&p.x), ax_ay);  // p.x and p.y are adjacent
    const double az = _mm_cvtsd_f64(az_bp), bp = _mm_cvtsd_f64(_mm_unpackhi_pd(az_bp, az_bp));
    const double e = _mm_cvtsd_f64(xax_yay) + _mm_cvtsd_f64(_mm_unpackhi_pd(xax_yay, xax_yay)) + p.z * az + 2 * bp +
                     (q.c + r.c);
    return e > 0 ? e : 0.0;
#else
    double s[12];
    for (int i = 0; i < 12; ++i) s[i] = q.pairs[i] + r.pairs[i];
    return Quadric::evaluate_terms(s[0], s[1], s[4], s[3], s[5], s[10], s[7], s[9], s[11], q.c + r.c, p);
#endif
  }
};

#if defined(VISIMP_PACKED_COST_QUADRIC)
static_assert(offsetof(Vec3, y) == offsetof(Vec3, x) + sizeof(double), "CostQuadric loads p.x and p.y as a pair");
#endif

inline void Quadric::evaluate_pair(const Vec3& p, const Vec3& r, double& qp, double& qr) const {
#if defined(VISIMP_PACKED_COST_QUADRIC)
  // Lane 0 is p, lane 1 is r; every operation is evaluate_terms' in its order (no FMA target).
  const __m128d x = _mm_set_pd(r.x, p.x), y = _mm_set_pd(r.y, p.y), z = _mm_set_pd(r.z, p.z);
  const auto dot3 = [&](double u, double v, double w) {
    return _mm_add_pd(_mm_add_pd(_mm_mul_pd(_mm_set1_pd(u), x), _mm_mul_pd(_mm_set1_pd(v), y)),
                      _mm_mul_pd(_mm_set1_pd(w), z));
  };
  const __m128d ax = dot3(a00, a01, a02), ay = dot3(a01, a11, a12), az = dot3(a02, a12, a22);
  const __m128d xax_yay_zaz =
      _mm_add_pd(_mm_add_pd(_mm_mul_pd(x, ax), _mm_mul_pd(y, ay)), _mm_mul_pd(z, az));
  const __m128d bp = dot3(b0, b1, b2);
  const __m128d e = _mm_add_pd(_mm_add_pd(xax_yay_zaz, _mm_add_pd(bp, bp)), _mm_set1_pd(c));
  // maxpd(e, 0) is e > 0 ? e : 0 lane by lane, NaN and -0 included.
  const __m128d clamped = _mm_max_pd(e, _mm_setzero_pd());
  qp = _mm_cvtsd_f64(clamped);
  qr = _mm_cvtsd_f64(_mm_unpackhi_pd(clamped, clamped));
#else
  qp = evaluate(p);
  qr = evaluate(r);
#endif
}

/// How place() chose the point (reported in tests and traces).
enum class PlacementKind {
  optimal,         ///< A well conditioned: the unique minimiser of Q
  pseudo_inverse,  ///< A (near) singular: minimiser in the well-determined directions, the
                   ///< rest taken from the edge midpoint (flat or cylindrical regions), by a
                   ///< damped solve (Q + kRankThreshold·trace·|x - mid|²)
  segment,         ///< the minimiser was unusable (too far away): best point on the edge
  endpoint0,       ///< endpoint p0 is as good as the minimiser (keeps its exact position)
  endpoint1,       ///< endpoint p1 is as good as the minimiser
};

struct Placement {
  Vec3 position;
  PlacementKind kind = PlacementKind::optimal;
  double error = 0;  ///< Q(position), clamped at 0: place() evaluates it anyway
};

/// Where the edge (p0, p1) with merged quadric q should collapse to.
///
/// An endpoint whose error is within rounding (1e-12 of the quadric's scale) of 0 is returned
/// at once: the optimum cannot be lower. Otherwise solves A x = -b: a closed-form inverse when
/// det(A) > 1e-3·trace(A)·(sum of its principal 2×2 minors), which guarantees cond(A) < 1e3,
/// else a damped solve relative to the edge midpoint (the minimiser of
/// Q(x) + 1e-3·trace(A)·|x - mid|²: Lindstrom's 2000 truncated pseudo-inverse up to a factor
/// per direction). A result farther than 2 edge lengths from the midpoint, or non-finite, falls
/// back to the minimiser of Q on the segment. Finally an endpoint whose error is within
/// rounding of the optimum is preferred, so flat and straight regions keep original vertex
/// positions exactly.
Placement place(const Quadric& q, const Vec3& p0, const Vec3& p1);

}  // namespace visimp
