// Perspective ID + depth views on the CPU: what a viewer at a point sees (the visibility
// field's queries, culled and full frames, missed pixels). The same triangle fill as the
// orthographic rasterizer (exact edge functions, top-left rule), plus clipping against the
// near plane and a guard band, which views from inside a scene need.
//
// Conventions: pixel (i, j) is row j from the bottom; its ray leaves the eye along
//   forward + ((2(i + 0.5)/R − 1)·right + (2(j + 0.5)/R − 1)·up)·tan(fov/2),
// so the field of view spans the image's width and height. Depth is 1 − near/z (z the
// distance along forward): 0 at the near plane, → 1 far away, affine in screen space.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/core/vec3.h"

namespace visimp {

struct PerspectiveView {
  Vec3 eye;                 ///< in the frame of the positions drawn
  Vec3 forward, right, up;  ///< orthonormal; right × up = −forward (y up, x right on screen)
  double tan_half_fov = 1;  ///< tan of half the field of view
  double near = 1e-3;       ///< distance of the near plane
  int resolution = 480;

  /// Looks from `eye` at `target`; up is +z unless the view is (nearly) vertical, then +y.
  static PerspectiveView looking_at(const Vec3& eye, const Vec3& target, double fov_degrees, int resolution,
                                    double near);
  /// The (unnormalised) direction of the ray through the centre of pixel (i, j).
  Vec3 pixel_ray(double i, double j) const;
};

struct PerspectiveFrame {
  std::vector<std::uint32_t> ids;  ///< R×R, face index + 1, 0 = background
  std::vector<float> depth;        ///< R×R
};

/// Draws faces (all, or the listed ones) of `positions`/`faces` from `view`, both sides.
/// Keeps scratch buffers between calls: one per thread.
class PerspectiveRasterizer {
 public:
  void draw(const std::vector<std::array<float, 3>>& positions, const std::vector<Face>& faces,
            const std::vector<std::uint32_t>* subset, const PerspectiveView& view, PerspectiveFrame& out);

 private:
  struct ViewVertex {
    float x, y, z;  // view space: x right, y up, z along forward
  };
  void draw_face(std::uint32_t f, const std::vector<Face>& faces, const PerspectiveView& view, PerspectiveFrame& out);
  std::vector<ViewVertex> view_vertices_;
  std::vector<std::uint32_t> stamp_;  // which vertices are transformed for the current frame
  std::uint32_t frame_ = 0;
};

}  // namespace visimp
