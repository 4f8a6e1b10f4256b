// Exact closest-triangle queries for Metro-style sampling: a binary bounding-volume
// hierarchy over a mesh's non-degenerate faces (median split of the centroids on the longest
// axis, ≤ 4 triangles a leaf). Each node holds both children's boxes (one cache line per
// step) in float, relative to the mesh's centre and rounded outwards by one more float step,
// so the box distances stay lower bounds for any coordinates (1e7 offsets included) while the
// triangles and the distances to them stay in double. Queries accept a hint — the triangle that was
// closest to the previous sample — because samples arrive face by face: the hint's distance
// is usually already the answer and prunes nearly the whole tree. Results never depend on
// the hint (only the time does), so they are identical for any thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

class ClosestTriangleIndex {
 public:
  static constexpr std::uint32_t kNoHint = ~std::uint32_t{0};

  /// Indexes the non-degenerate faces of `mesh`; empty() when it has none. Built on up to
  /// `threads` threads (0: the hardware's); the tree is the same for any count.
  explicit ClosestTriangleIndex(const Mesh& mesh, unsigned threads = 0);

  bool empty() const { return triangles_.empty(); }

  /// Squared distance from p to the nearest indexed triangle. `hint` (in/out): a triangle to
  /// try first, replaced by the nearest one found; start with kNoHint.
  double squared_distance(const Vec3& p, std::uint32_t& hint) const;

  /// For a running maximum of such distances: the squared distance to the nearest triangle
  /// when it is above `bound`, otherwise some value <= bound, so that max(bound, result) is
  /// always max(bound, squared_distance(p)). The search stops at the first triangle within
  /// `bound` — most often the hint's, without a step into the tree — and then leaves `hint` at
  /// a triangle within the bound rather than the nearest (a starting point still: only the
  /// time depends on it).
  double squared_distance_past(const Vec3& p, std::uint32_t& hint, double bound) const;

  /// The same for points[0..n) (close together, e.g. one face's samples in Morton order),
  /// into squared[0..n). Faster than one query each: points are taken in groups; a group's
  /// first point gets a full query whose triangle bounds every distance in the group (U), and
  /// the rest are compared only with the triangles whose boxes lie within U of the group's box.
  void squared_distances(const Vec3* points, std::size_t n, double* squared, std::uint32_t& hint) const;

 private:
  struct Triangle {
    Vec3 a, ab, ac;  // a and its two edge vectors: what the closest-point test needs
  };
  struct Box {
    float lo[3], hi[3];
  };
  // Child reference: inner node index, or kLeaf | first triangle (with count in `leaf_size`).
  static constexpr std::uint32_t kLeaf = 0x80000000u;
  struct alignas(64) Node {
    Box box[2];
    std::uint32_t child[2];
    std::uint8_t leaf_size[2];
  };

  // Where a subtree goes: its first node and first triangle.
  struct Slots {
    std::uint32_t node, triangle;
  };
  // A built subtree's box (absolute, double, and rounded out relative to centre_) and its leaf size (0: a node).
  struct Built {
    Vec3 lo, hi;
    Box box;
    std::uint8_t leaf_size = 0;
  };
  // squared_distance(), or with kBounded squared_distance_past().
  template <bool kBounded>
  double search(const Vec3& p, std::uint32_t& hint, double bound) const;

  // Subtrees this large build their halves on two threads.
  static constexpr std::uint32_t kParallelTriangles = std::uint32_t(1) << 16;
  static std::uint32_t subtree_nodes(std::uint32_t n);
  // Builds the subtree of order[begin, end) at `at`; returns its reference.
  std::uint32_t build(std::vector<std::uint32_t>& order, const std::vector<Vec3>& centroid, std::uint32_t begin,
                      std::uint32_t end, const Mesh& mesh, const Slots& at, unsigned workers, Built& out);

  Vec3 centre_;                      // boxes are relative to it
  std::vector<Triangle> triangles_;  // in leaf order, absolute coordinates
  std::vector<Node> nodes_;
  std::uint32_t root_ = 0;
  std::uint8_t root_leaf_size_ = 0;
  Box root_box_{};
};

/// Squared distance from p to the triangle (a, a + ab, a + ac) (Ericson, Real-Time Collision
/// Detection §5.1.5: Voronoi regions of the vertices and edges, then the interior).
double point_triangle_squared_distance(const Vec3& p, const Vec3& a, const Vec3& ab, const Vec3& ac);

}  // namespace visimp
