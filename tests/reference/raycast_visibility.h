// An independent reference for visimp's visibility measure: V computed pointwise with
// Embree ray casting instead of rasterized ID and depth buffers. A dependency of tests and
// bench only, never of the library.
//
// The same measure (Zhang & Turk 2002, eq. 4.3, with visimp's winding rule: closed surfaces
// from outside, open ones from their better-seen side; core/orientation.h), sampled
// differently:
//   - faces are refined until no edge exceeds `max_edge_fraction` of the bounding-sphere
//     diameter (so F is nearly constant over a sub-face);
//   - per camera, one orthographic ray per pixel centre: a sub-face hit by a ray is seen;
//   - the vertex rule, exactly: a sub-face is also seen when one of its vertices is not
//     occluded (a shadow ray from the camera plane to the vertex meets nothing before it);
//   - V of an input face is the area-weighted mean of its sub-faces' V.
// Both backends of visimp share frame.h's projection; this one shares only the camera
// directions and the view of the bounding sphere.
#pragma once

#include <cstddef>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/mesh.h"

namespace visimp::reference {

struct RaycastOptions {
  int resolution = 1024;             ///< rays per image side
  double max_edge_fraction = 0.008;  ///< of the bounding-sphere diameter
  /// A vertex is occluded only by a hit more than this fraction of the diameter in front of it.
  double vertex_epsilon = 1e-6;
  bool vertex_rule = true;  ///< off: only faces a ray hits are seen
  unsigned threads = 0;     ///< 0 = one per hardware thread
};

struct RaycastVisibility {
  std::vector<float> face;          ///< V per input face
  double mesh = 0;                  ///< V(M), area-weighted
  double hidden_area_fraction = 0;  ///< area with V = 0 (never seen)
  std::size_t refined_faces = 0;
  double seconds = 0;
};

RaycastVisibility raycast_visibility(const Mesh& mesh, const CameraSet& cameras, const RaycastOptions& options = {});

/// How visimp's V compares with a reference, per face and by area.
struct VisibilityAgreement {
  double mean_abs_difference = 0;  ///< area-weighted mean |ΔV| over faces
  double mesh_difference = 0;      ///< V(M) − V_ref(M)
  double hidden_area_low = 0;      ///< of the area the reference never sees, the share with V ≤ 0.02
};
VisibilityAgreement compare_visibility(const Mesh& mesh, const std::vector<float>& v, const RaycastVisibility& ref);

}  // namespace visimp::reference
