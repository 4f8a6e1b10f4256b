// Which samples surround a viewing direction (view reconstruction, step 1).
//
//   octahedron sets (Meruvia Pastor §3.3.1): the leaf face of the subdivided octahedron that
//     the ray from the centre toward the viewer hits, found by descending the subdivision
//     hierarchy (SphereTessellation::locate); its 3 vertices are the samples.
//   any other set (Meruvia Pastor & Strothotte §3.2.1): the convex hull of the camera
//     directions (CGAL) triangulates them; the hull face whose cone holds the direction is
//     found by a walk from a cube-map start table, and its 3 vertices plus the opposite
//     vertices of its 3 edge-neighbours are the samples (up to 6 distinct).
//
// A "cell" is that leaf or hull face: every direction in a cell selects the same samples,
// which is what lets a reconstructor precompute one joined bitfield per cell.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/vec3.h"

namespace visimp {

struct SampleChoice {
  std::array<std::uint32_t, 6> samples{};
  std::size_t count = 0;
};

class SampleSelector {
 public:
  /// Uses the hierarchy when `cameras` is exactly an octahedron level's set, else the hull.
  /// Throws UsageError when a hull cannot surround the centre (fewer than 4 directions, all
  /// in one plane or one half-space).
  explicit SampleSelector(const CameraSet& cameras);
  ~SampleSelector();
  SampleSelector(SampleSelector&&) noexcept;
  SampleSelector& operator=(SampleSelector&&) noexcept;

  bool hierarchical() const;
  /// Number of cells (leaf or hull faces).
  std::size_t cells() const;
  /// The cell holding `direction` (any non-zero vector).
  std::uint32_t cell(const Vec3& direction) const;
  /// The samples a viewer in any direction of `cell` joins.
  SampleChoice samples_of_cell(std::uint32_t cell) const;
  /// The three samples at the corners of `cell`.
  std::array<std::uint32_t, 3> corners(std::uint32_t cell) const;
  SampleChoice select(const Vec3& direction) const { return samples_of_cell(cell(direction)); }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The octahedron level whose camera set `cameras` is exactly, or -1.
int octahedron_level_of(const CameraSet& cameras);

}  // namespace visimp
