// Quadric error metrics: Garland & Heckbert, "Surface Simplification Using Quadric Error
// Metrics", SIGGRAPH 1997; rank-revealing placement after Lindstrom, "Out-of-core
// simplification of large polygonal models", SIGGRAPH 2000.
#include "visimp/simplify/quadric.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace visimp {

namespace {
constexpr double kRankThreshold = 1e-3;   // eigenvalues below this·λmax count as zero
constexpr double kMaxReachInEdges = 2.0;  // a placement farther than this from the midpoint is rejected
}  // namespace

Quadric Quadric::plane(const Vec3& n, const Vec3& point, double weight) {
  const double d = -dot(n, point);
  Quadric q;
  q.a00 = weight * n.x * n.x;
  q.a01 = weight * n.x * n.y;
  q.a02 = weight * n.x * n.z;
  q.a11 = weight * n.y * n.y;
  q.a12 = weight * n.y * n.z;
  q.a22 = weight * n.z * n.z;
  q.b0 = weight * n.x * d;
  q.b1 = weight * n.y * d;
  q.b2 = weight * n.z * d;
  q.c = weight * d * d;
  q.area = weight;
  return q;
}

namespace {

// Minimiser of Q on p0 + t(p1 - p0), t in [0, 1].
Vec3 best_on_segment(const Quadric& q, const Vec3& p0, const Vec3& p1) {
  const Vec3 d = p1 - p0;
  const Vec3 ad{q.a00 * d.x + q.a01 * d.y + q.a02 * d.z, q.a01 * d.x + q.a11 * d.y + q.a12 * d.z,
                q.a02 * d.x + q.a12 * d.y + q.a22 * d.z};
  const double curvature = dot(d, ad);
  double t = 0.5;
  if (curvature > 0) {
    const double slope = dot(ad, p0) + q.b0 * d.x + q.b1 * d.y + q.b2 * d.z;
    t = std::clamp(-slope / curvature, 0.0, 1.0);
  }
  return p0 + d * t;
}

}  // namespace

Placement place(const Quadric& q, const Vec3& p0, const Vec3& p1) {
  const Vec3 mid = (p0 + p1) * 0.5;
  const double trace = q.a00 + q.a11 + q.a22;
  Placement result{mid, PlacementKind::optimal};

  // Cofactors of A: the closed-form inverse is adj(A)/det(A).
  const double c00 = q.a11 * q.a22 - q.a12 * q.a12;
  const double c01 = q.a02 * q.a12 - q.a01 * q.a22;
  const double c02 = q.a01 * q.a12 - q.a02 * q.a11;
  const double c11 = q.a00 * q.a22 - q.a02 * q.a02;
  const double c12 = q.a01 * q.a02 - q.a00 * q.a12;
  const double c22 = q.a00 * q.a11 - q.a01 * q.a01;
  const double det = q.a00 * c00 + q.a01 * c01 + q.a02 * c02;
  // For symmetric PSD A with eigenvalues l1 >= l2 >= l3: l1 <= trace and
  // l1·l2 <= c00 + c11 + c22 (sum of principal minors), so l3/l1 >= det / (trace·minors).
  // Above the rank threshold no eigenvalue would be truncated: the plain inverse is exact.
  const double minors = c00 + c11 + c22;
  if (trace > 0 && det > kRankThreshold * trace * minors) {
    const double inv = -1.0 / det;
    result.position = {(c00 * q.b0 + c01 * q.b1 + c02 * q.b2) * inv, (c01 * q.b0 + c11 * q.b1 + c12 * q.b2) * inv,
                       (c02 * q.b0 + c12 * q.b1 + c22 * q.b2) * inv};
  } else if (trace > 0) {
    Eigen::Matrix3d a;
    a << q.a00, q.a01, q.a02, q.a01, q.a11, q.a12, q.a02, q.a12, q.a22;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
    eigen.computeDirect(a);
    const Eigen::Vector3d& lambda = eigen.eigenvalues();  // ascending
    const Eigen::Vector3d m(mid.x, mid.y, mid.z);
    const Eigen::Vector3d residual = -Eigen::Vector3d(q.b0, q.b1, q.b2) - a * m;
    Eigen::Vector3d x = m;
    for (int i = 0; i < 3; ++i) {
      if (lambda[i] > kRankThreshold * lambda[2]) {
        const Eigen::Vector3d u = eigen.eigenvectors().col(i);
        x += u * (u.dot(residual) / lambda[i]);
      }
    }
    result = {{x[0], x[1], x[2]}, PlacementKind::pseudo_inverse};
  }
  const double reach = kMaxReachInEdges * norm(p1 - p0);
  if (!is_finite(result.position) || norm(result.position - mid) > reach) {
    result = {best_on_segment(q, p0, p1), PlacementKind::segment};
  }

  // Prefer an endpoint whose error equals the optimum up to rounding (~1e-12 of the
  // quadric's scale): keeps original coordinates on flat and straight parts.
  const double best = q.evaluate(result.position);
  const double tolerance = 1e-12 * (trace + std::abs(q.c)) + 1e-300;
  const double e0 = q.evaluate(p0), e1 = q.evaluate(p1);
  if (std::min(e0, e1) <= best + tolerance) {
    result = e0 <= e1 ? Placement{p0, PlacementKind::endpoint0, e0} : Placement{p1, PlacementKind::endpoint1, e1};
  } else {
    result.error = best;
  }
  return result;
}

}  // namespace visimp
