// What a frame backend produces for one orthographic camera: a face-ID buffer and a depth
// buffer at R×R (Zhang & Turk 2002, §4: "render the mesh ... with a color-encoding of the
// polygon ID"), plus the projection that made them so consumers can project vertices the
// same way.
//
// Image conventions (shared by every backend):
//   - The view covers the scene's bounding sphere: world point p maps to
//       x = (p·right / radius + 1) · R/2,  y = (p·up / radius + 1) · R/2      (pixels)
//       depth = (1 - p·direction / radius) / 2                          (0 nearest, 1 far)
//     with p relative to the sphere centre and right × up = direction, so a face whose
//     normal points toward the camera is counter-clockwise on screen.
//   - Pixel (i, j) is row j from the bottom, column i from the left; its centre is
//     (i + 0.5, j + 0.5). A pixel belongs to a triangle when its centre is inside it or on
//     a top or left edge (the fill rule of Direct3D and OpenGL implementations).
//   - ids[j·R + i] = face index + 1, 0 = background; depth = 1 for background.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "visimp/core/bounding_box.h"
#include "visimp/core/mesh.h"
#include "visimp/core/vec3.h"

namespace visimp {

/// The normals of a run of consecutive faces lie within a cone: when a camera direction d
/// has dot(axis, d) < cutoff, every face of the run turns its back to that camera.
struct NormalCone {
  std::array<float, 3> axis{0, 0, 0};
  float cutoff = -2;  ///< -sin(half-angle) minus a margin; -2 (never) for a cone of 90° or more

  bool all_back_facing(const std::array<float, 3>& d) const {
    return axis[0] * d[0] + axis[1] * d[1] + axis[2] * d[2] < cutoff;
  }
};

/// The same for the faces around one vertex, packed in 4 bytes (a per-vertex loop is bound by
/// its loads): axis and cutoff scaled by 127, the cutoff lowered by the axis's rounding.
struct VertexCone {
  std::array<std::int8_t, 4> packed{0, 0, 0, -128};  ///< -128: never all turned away

  bool all_back_facing(const std::array<float, 3>& d) const {
    return static_cast<float>(packed[0]) * d[0] + static_cast<float>(packed[1]) * d[1] +
               static_cast<float>(packed[2]) * d[2] <
           static_cast<float>(packed[3]);
  }
};

/// Radius of the sphere every view covers: half the box diagonal plus 1%, so no vertex
/// projects onto the image border or to depth exactly 0 or 1 (1 for an empty or point box).
double view_radius(const BoundingBox& box);

/// Geometry prepared for rendering: positions relative to the bounding-sphere centre, in
/// float (relative coordinates keep float precise however far the mesh is from the origin).
struct RenderScene {
  static constexpr std::size_t kClusterSize = 64;

  std::vector<std::array<float, 3>> positions;
  std::vector<Face> faces;
  double radius = 1;  ///< bounding-sphere radius, in the units of `positions`
  /// Faces [0, culled_faces) are not drawn when they turn their back to the camera (exact
  /// only for faces of closed, outward-wound surfaces: see core/orientation.h); the rest
  /// are drawn from both sides.
  std::size_t culled_faces = 0;
  /// Empty, or one cone per kClusterSize consecutive faces: lets a backend that culls back
  /// faces, and a consumer that ignores them, skip whole clusters. Worth it when faces are
  /// in a spatially coherent order (see visibility.cpp).
  std::vector<NormalCone> clusters;
  /// Empty, or one cone per vertex over the faces that use it: a consumer may skip
  /// per-vertex work for a camera that every one of those faces turns its back to.
  std::vector<VertexCone> vertex_cones;
  /// Empty, or one cone per kClusterSize consecutive vertices over every face that uses one
  /// of them: the same, a run of vertices at a time.
  std::vector<NormalCone> vertex_clusters;

  /// Fills `clusters`, `vertex_cones` and `vertex_clusters` from the given unit face normals (zero for
  /// degenerate faces, which never face a camera). A cluster or vertex with a face at or
  /// past culled_faces is never skipped. `threads` (0 = one per hardware thread) share the
  /// work; the cones do not depend on it.
  void compute_normal_cones(const std::vector<std::array<float, 3>>& unit_normals, unsigned threads = 0);

  static RenderScene from_mesh(const Mesh& mesh, bool cull_back_faces);
  /// The same in a given frame (to render several meshes from identical views).
  static RenderScene from_mesh(const Mesh& mesh, bool cull_back_faces, const Vec3& center, double radius);
};

/// An orthographic camera on the bounding sphere looking at its centre.
struct OrthoView {
  Vec3 direction;  ///< unit vector from the centre toward the camera
  Vec3 right, up;  ///< image axes; right × up = direction
  double radius = 1;
  int resolution = 480;

  static OrthoView looking_from(const Vec3& direction, double radius, int resolution);
};

/// One vertex in screen space: pixel coordinates and depth as defined above.
struct ScreenVertex {
  float x, y, depth;
};

/// Projects every scene vertex for `view` (the one projection all backends and consumers use).
void project_vertices(const RenderScene& scene, const OrthoView& view, std::vector<ScreenVertex>& out);

struct Frame {
  OrthoView view;
  std::vector<std::uint32_t> ids;      ///< R×R, face index + 1, 0 = background
  std::vector<float> depth;            ///< R×R, 0 nearest .. 1 far/background
  std::vector<ScreenVertex> vertices;  ///< every scene vertex projected with `view`

  int resolution() const { return view.resolution; }
};

}  // namespace visimp
