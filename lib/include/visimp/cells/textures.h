// Projective textures for SVMeshes and MVMeshes (walkthrough-LOD paper §3.1–3.2): the object,
// drawn whole and shaded, is photographed from the cell's eyes — the centre for an SVMesh; the
// centre and the six corners for an MVMesh, which then blends them by view direction (the
// paper's view-dependent projective texture mapping). A texture keeps the luminance and the
// depth of what it saw, cropped to the object, so a point of the LOD mesh takes the original's
// grey only where the texture saw that surface (its depth agrees) and is shaded otherwise.
#pragma once

#include <cstdint>
#include <vector>

#include "visimp/core/vec3.h"
#include "visimp/render/perspective.h"

namespace visimp {

struct ProjectiveTexture {
  PerspectiveView view;              ///< eye in scene coordinates; resolution² image
  int x0 = 0, y0 = 0, width = 0, height = 0;  ///< the crop kept, in pixels of that image
  float near_distance = 0, far_distance = 0;  ///< depth quantisation range (along view.forward)
  std::vector<std::uint8_t> y;       ///< width × height luminance, rows bottom to top
  std::vector<std::uint16_t> depth;  ///< quantised distance along view.forward; kNoDepth: nothing seen
  static constexpr std::uint16_t kNoDepth = 0xffff;

  /// The grey this texture saw at scene point `p`, if it saw p's surface: p projects inside the
  /// crop and its distance is within `tolerance` (a fraction of the distance) of the depth seen.
  bool sample(const Vec3& p, double tolerance, float* grey) const;
  std::size_t bytes() const { return y.size() * 3; }
};

}  // namespace visimp
