// Certified Hausdorff bounds through CGAL (see bounded_hausdorff.h).
#include "visimp/metrics/bounded_hausdorff.h"

// CGAL 5.5 distance.h uses CGAL::midpoint for Point_3 without including it (CGAL issue #8009).
#include <CGAL/Kernel/global_functions_3.h>
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>

#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"

namespace visimp {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;

// Every non-degenerate face as its own triangle: the distance depends only on the set of
// triangles, and unshared vertices accept any input (non-manifold, misoriented) as is.
SurfaceMesh triangle_soup(const Mesh& m) {
  SurfaceMesh out;
  for (const Face& f : m.faces) {
    if (is_degenerate(m, f)) continue;
    SurfaceMesh::Vertex_index v[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = m.positions[f[k]];
      v[k] = out.add_vertex(Kernel::Point_3(p.x, p.y, p.z));
    }
    out.add_face(v[0], v[1], v[2]);
  }
  if (out.number_of_faces() == 0) throw InvalidMeshError("bounded Hausdorff: a mesh has no non-degenerate face");
  return out;
}

}  // namespace

HausdorffBounds bounded_hausdorff(const Mesh& a, const Mesh& b, double tolerance, double known_lower) {
  const auto start = std::chrono::steady_clock::now();
  if (!(tolerance > 0)) throw InvalidMeshError("bounded Hausdorff: the tolerance must be positive");
  const SurfaceMesh sa = triangle_soup(a), sb = triangle_soup(b);
  namespace PMP = CGAL::Polygon_mesh_processing;
  HausdorffBounds r;
  r.estimate = PMP::bounded_error_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(sa, sb, tolerance);
  r.lower = std::max(known_lower, std::max(0.0, r.estimate - tolerance));
  r.upper = r.estimate + tolerance;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace visimp
