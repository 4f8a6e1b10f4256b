// visimp meshes to and from OpenMesh, face V as an OpenMesh property, and simplification in
// place. Header-only: include it where you already link OpenMesh (OpenMeshCore); visimp
// itself does not depend on OpenMesh (docs/interop.md).
#pragma once

#include <OpenMesh/Core/Mesh/Handles.hh>
#include <OpenMesh/Core/Utils/Property.hh>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "visimp/core/errors.h"
#include "visimp/core/mesh.h"
#include "visimp/interop/simplify_converted.h"
#include "visimp/simplify/simplify.h"

namespace visimp::interop {

/// The face property visibility is stored in, unless a caller names another.
inline constexpr const char* kOpenMeshVisibility = "visimp:V";

/// An OpenMesh mesh (TriMesh or PolyMesh, any point type) as a visimp Mesh. Deleted elements
/// are skipped and indices compacted in iteration order; polygons are fanned from their first
/// vertex. A float face property named `visibility` (when present) becomes face_quality, copied
/// to every triangle of a fan.
template <class OMesh>
Mesh from_openmesh(const OMesh& om, const std::string& visibility = kOpenMeshVisibility) {
  Mesh out;
  std::vector<VertexIndex> index(om.n_vertices(), 0);
  out.positions.reserve(om.n_vertices());
  for (auto v : om.vertices()) {
    index[static_cast<std::size_t>(v.idx())] = static_cast<VertexIndex>(out.positions.size());
    const auto& p = om.point(v);
    out.positions.push_back({double(p[0]), double(p[1]), double(p[2])});
  }
  OpenMesh::FPropHandleT<float> v_property;
  const bool has_v = om.get_property_handle(v_property, visibility);
  std::vector<VertexIndex> ring;
  for (auto f : om.faces()) {
    ring.clear();
    for (auto v : om.fv_range(f)) ring.push_back(index[static_cast<std::size_t>(v.idx())]);
    for (std::size_t k = 1; k + 1 < ring.size(); ++k) {
      out.faces.push_back({ring[0], ring[k], ring[k + 1]});
      if (has_v) out.face_quality.push_back(om.property(v_property, f));
    }
  }
  return out;
}

/// Replaces `out`'s contents with `mesh` (vertex i is handle i, face j handle j unless refused).
/// OpenMesh's half-edge structure cannot hold a face over a complex edge or vertex (three faces
/// on an edge, a face against the others' orientation): with `refused` such faces are skipped
/// and counted; without it the first one throws InvalidMeshError. Face quality, when present,
/// goes to the `visibility` property.
template <class OMesh>
void to_openmesh(const Mesh& mesh, OMesh& out, std::size_t* refused = nullptr,
                 const std::string& visibility = kOpenMeshVisibility) {
  using Point = typename OMesh::Point;
  using Scalar = typename Point::value_type;
  out.clear();
  std::vector<typename OMesh::VertexHandle> handle;
  handle.reserve(mesh.num_vertices());
  for (const Vec3& p : mesh.positions)
    handle.push_back(out.add_vertex(Point(static_cast<Scalar>(p.x), static_cast<Scalar>(p.y), static_cast<Scalar>(p.z))));
  OpenMesh::FPropHandleT<float> v_property;
  if (mesh.has_face_quality() && !out.get_property_handle(v_property, visibility)) out.add_property(v_property, visibility);
  if (refused) *refused = 0;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Face& t = mesh.faces[f];
    const auto face = out.add_face(handle[t[0]], handle[t[1]], handle[t[2]]);
    if (!face.is_valid()) {
      if (!refused)
        throw InvalidMeshError("OpenMesh cannot hold face " + std::to_string(f) +
                               " (a complex edge or vertex: non-manifold or inconsistently wound)");
      ++*refused;
      continue;
    }
    if (mesh.has_face_quality()) out.property(v_property, face) = mesh.face_quality[f];
  }
}

/// Stores per-face V (Visibility::face, or any per-face value) in the float face property
/// `name`, creating it when missing. Throws UsageError when the count is not one per face.
template <class OMesh>
OpenMesh::FPropHandleT<float> set_visibility_property(OMesh& om, const std::vector<float>& face_visibility,
                                                      const std::string& name = kOpenMeshVisibility) {
  if (face_visibility.size() != om.n_faces())
    throw UsageError("set_visibility_property: " + std::to_string(face_visibility.size()) + " values for " +
                     std::to_string(om.n_faces()) + " faces");
  OpenMesh::FPropHandleT<float> property;
  if (!om.get_property_handle(property, name)) om.add_property(property, name);
  for (auto f : om.all_faces()) om.property(property, f) = face_visibility[static_cast<std::size_t>(f.idx())];
  return property;
}

/// Simplifies `om` with visimp's engine and puts the result back into it (garbage-collected,
/// polygons fanned first). With options.method = vg and no options.face_visibility, V comes
/// from the `visibility` face property (UsageError when it is missing). Surviving faces keep
/// their V property; other properties are not carried over.
template <class OMesh>
SimplifyResult simplify_in_place(OMesh& om, SimplifyOptions options,
                                 const std::string& visibility = kOpenMeshVisibility) {
  const Simplified s = simplify_converted(from_openmesh(om, visibility), std::move(options), visibility);
  to_openmesh(s.mesh, om, nullptr, visibility);
  return s.result;
}

}  // namespace visimp::interop
