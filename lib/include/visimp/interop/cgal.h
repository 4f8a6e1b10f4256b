// visimp meshes to and from CGAL::Surface_mesh, face V as a Surface_mesh property map, and
// simplification in place. Header-only: include it where you already use CGAL; visimp's
// public targets do not depend on CGAL (docs/interop.md).
#pragma once

#include <CGAL/Surface_mesh.h>
#include <CGAL/number_utils.h>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "visimp/core/errors.h"
#include "visimp/core/mesh.h"
#include "visimp/interop/simplify_converted.h"
#include "visimp/simplify/simplify.h"

namespace visimp::interop {

/// The face property map visibility is stored in, unless a caller names another.
inline constexpr const char* kCgalVisibility = "f:visimp_V";

/// A Surface_mesh (any kernel's point, exact ones included: coordinates go through
/// CGAL::to_double) as a visimp Mesh. Removed elements are skipped and indices compacted in
/// iteration order; polygons are fanned from their first vertex. A float face map named
/// `visibility` (when present) becomes face_quality, copied to every triangle of a fan.
template <class Point>
Mesh from_cgal(const CGAL::Surface_mesh<Point>& sm, const std::string& visibility = kCgalVisibility) {
  using SM = CGAL::Surface_mesh<Point>;
  Mesh out;
  std::vector<VertexIndex> index(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  out.positions.reserve(sm.number_of_vertices());
  for (typename SM::Vertex_index v : sm.vertices()) {
    index[static_cast<std::size_t>(v)] = static_cast<VertexIndex>(out.positions.size());
    const Point& p = sm.point(v);
    out.positions.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
  }
  // CGAL 5.5: (map, found).
  const auto [v_map, has_v] = sm.template property_map<typename SM::Face_index, float>(visibility);
  std::vector<VertexIndex> ring;
  for (typename SM::Face_index f : sm.faces()) {
    ring.clear();
    for (typename SM::Vertex_index v : CGAL::vertices_around_face(sm.halfedge(f), sm))
      ring.push_back(index[static_cast<std::size_t>(v)]);
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) {
      out.faces.push_back({ring[0], ring[k], ring[k + 1]});
      if (has_v) out.face_quality.push_back(v_map[f]);
    }
  }
  return out;
}

/// Replaces `out`'s contents with `mesh` (vertex i is index i, face j index j unless refused).
/// A Surface_mesh cannot hold a face over a complex edge or vertex (three faces on an edge, a
/// face against the others' orientation): with `refused` such faces are skipped and counted;
/// without it the first one throws InvalidMeshError. Face quality, when present, goes to the
/// `visibility` face map.
template <class Point>
void to_cgal(const Mesh& mesh, CGAL::Surface_mesh<Point>& out, std::size_t* refused = nullptr,
             const std::string& visibility = kCgalVisibility) {
  using SM = CGAL::Surface_mesh<Point>;
  out.clear();
  out.reserve(static_cast<typename SM::size_type>(mesh.num_vertices()),
              static_cast<typename SM::size_type>(3 * mesh.num_faces() / 2),
              static_cast<typename SM::size_type>(mesh.num_faces()));
  std::vector<typename SM::Vertex_index> handle;
  handle.reserve(mesh.num_vertices());
  for (const Vec3& p : mesh.positions) handle.push_back(out.add_vertex(Point(p.x, p.y, p.z)));
  typename SM::template Property_map<typename SM::Face_index, float> v_map;
  if (mesh.has_face_quality()) v_map = out.template add_property_map<typename SM::Face_index, float>(visibility, 0.f).first;
  if (refused) *refused = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Face& t = mesh.faces[f];
    const typename SM::Face_index face = out.add_face(handle[t[0]], handle[t[1]], handle[t[2]]);
    if (face == SM::null_face()) {
      if (!refused)
        throw InvalidMeshError("CGAL::Surface_mesh cannot hold face " + std::to_string(f) +
                               " (a complex edge or vertex: non-manifold or inconsistently wound)");
      ++*refused;
      continue;
    }
    if (mesh.has_face_quality()) v_map[face] = mesh.face_quality[f];
  }
}

/// Stores per-face V (Visibility::face, or any per-face value, in face-index order) in the float
/// face map `name`, creating it when missing. Throws UsageError when the count is not one per face.
template <class Point>
typename CGAL::Surface_mesh<Point>::template Property_map<typename CGAL::Surface_mesh<Point>::Face_index, float>
set_visibility_map(CGAL::Surface_mesh<Point>& sm, const std::vector<float>& face_visibility,
                   const std::string& name = kCgalVisibility) {
  using SM = CGAL::Surface_mesh<Point>;
  if (face_visibility.size() != sm.number_of_faces())
    throw UsageError("set_visibility_map: " + std::to_string(face_visibility.size()) + " values for " +
                     std::to_string(sm.number_of_faces()) + " faces");
  auto map = sm.template add_property_map<typename SM::Face_index, float>(name, 0.f).first;
  std::size_t k = 0;
  for (typename SM::Face_index f : sm.faces()) map[f] = face_visibility[k++];
  return map;
}

/// Simplifies `sm` with visimp's engine and puts the result back into it (compacted, polygons
/// fanned first). With options.method = vg and no options.face_visibility, V comes from the
/// `visibility` face map (UsageError when it is missing). Surviving faces keep their V; other
/// property maps are not carried over.
template <class Point>
SimplifyResult simplify_in_place(CGAL::Surface_mesh<Point>& sm, SimplifyOptions options,
                                 const std::string& visibility = kCgalVisibility) {
  const Simplified s = simplify_converted(from_cgal(sm, visibility), std::move(options), visibility);
  to_cgal(s.mesh, sm, nullptr, visibility);
  return s.result;
}

}  // namespace visimp::interop
