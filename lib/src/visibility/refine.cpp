/* Midpoint refinement (see refine.h). Each round finds the long edges once (sorted keys),
 * gives each a midpoint, then rewrites every face by which of its edges were split:
 *
 *   one split (e0)        two splits (e0, e1)          three splits
 *        v2                     v2                          v2
 *       / |\                   /  \                        /  \
 *      /  | \                 /    m12                   m20---m12
 *     /   |  \               /   /   \                  /  \  /  \
 *   v0----m---v1          v0---m01----v1              v0---m01---v1
 *
 * The two-split quad (v0, m01, m12, v2) is cut along its shorter diagonal.
 */
#include "visimp/visibility/refine.h"

#include <algorithm>
#include <numeric>

#include "visimp/core/errors.h"

namespace visimp {
namespace {

std::uint64_t edge_key(VertexIndex a, VertexIndex b) { return (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b); }

}  // namespace

double refinement_edge_length(double bounding_radius, int resolution, double worst_view_cosine) {
  const double pixel = 2.0 * bounding_radius / resolution;
  return pixel / worst_view_cosine;
}

bool has_edge_longer_than(const Mesh& mesh, double max_edge) {
  const double limit2 = max_edge * max_edge;
  for (const Face& f : mesh.faces) {
    for (int i = 0; i < 3; ++i) {
      if (squared_norm(mesh.positions[f[i]] - mesh.positions[f[(i + 1) % 3]]) > limit2) return true;
    }
  }
  return false;
}

std::optional<RefinedMesh> refine_long_edges(const Mesh& mesh, double max_edge, std::size_t max_faces) {
  if (!(max_edge > 0)) throw UsageError("refinement edge length must be positive");
  if (!has_edge_longer_than(mesh, max_edge)) return std::nullopt;  // nothing copied
  return refine_long_edges(Mesh{mesh.positions, mesh.faces, {}, {}}, max_edge, max_faces);
}

std::optional<RefinedMesh> refine_long_edges(Mesh&& mesh, double max_edge, std::size_t max_faces) {
  if (!(max_edge > 0)) throw UsageError("refinement edge length must be positive");
  const double limit2 = max_edge * max_edge;
  auto is_long = [&](const std::vector<Vec3>& p, VertexIndex a, VertexIndex b) {
    return squared_norm(p[a] - p[b]) > limit2;
  };
  std::optional<RefinedMesh> refined;
  for (;;) {
    const Mesh& current = refined ? refined->mesh : mesh;
    std::vector<std::uint64_t> long_edges;
    for (const Face& f : current.faces) {
      for (int i = 0; i < 3; ++i) {
        const VertexIndex a = f[i], b = f[(i + 1) % 3];
        if (is_long(current.positions, a, b)) long_edges.push_back(edge_key(a, b));
      }
    }
    if (long_edges.empty()) return refined;
    if (!refined) {
      refined.emplace();
      refined->mesh.positions = std::move(mesh.positions);
      refined->mesh.faces = std::move(mesh.faces);
      refined->input_face.resize(refined->mesh.faces.size());
      std::iota(refined->input_face.begin(), refined->input_face.end(), 0u);
    }
    Mesh& m = refined->mesh;
    std::sort(long_edges.begin(), long_edges.end());
    long_edges.erase(std::unique(long_edges.begin(), long_edges.end()), long_edges.end());
    if (m.positions.size() + long_edges.size() > 0xfffffff0u) {
      throw UsageError(
          "refinement would need more than 2^32 vertices (a coarser resolution makes the edge limit longer)");
    }
    const VertexIndex first_midpoint = static_cast<VertexIndex>(m.positions.size());
    for (std::uint64_t key : long_edges) {
      const auto a = static_cast<VertexIndex>(key >> 32), b = static_cast<VertexIndex>(key & 0xffffffffu);
      m.positions.push_back((m.positions[a] + m.positions[b]) * 0.5);
    }
    // 0 when the edge a-b was not split.
    auto midpoint = [&](VertexIndex a, VertexIndex b) -> VertexIndex {
      const std::uint64_t key = edge_key(a, b);
      const auto it = std::lower_bound(long_edges.begin(), long_edges.end(), key);
      if (it == long_edges.end() || *it != key) return 0;
      return first_midpoint + static_cast<VertexIndex>(it - long_edges.begin());
    };

    std::vector<Face> faces;
    std::vector<std::uint32_t> parents;
    faces.reserve(m.faces.size() * 2);
    parents.reserve(m.faces.size() * 2);
    for (std::size_t fi = 0; fi < m.faces.size(); ++fi) {
      const Face& f = m.faces[fi];
      const std::uint32_t parent = refined->input_face[fi];
      const VertexIndex mid[3] = {midpoint(f[0], f[1]), midpoint(f[1], f[2]), midpoint(f[2], f[0])};
      const int splits = (mid[0] != 0) + (mid[1] != 0) + (mid[2] != 0);
      auto emit = [&](VertexIndex a, VertexIndex b, VertexIndex c) {
        faces.push_back({a, b, c});
        parents.push_back(parent);
      };
      if (splits == 0) {
        emit(f[0], f[1], f[2]);
      } else if (splits == 3) {
        emit(f[0], mid[0], mid[2]);
        emit(mid[0], f[1], mid[1]);
        emit(mid[2], mid[1], f[2]);
        emit(mid[0], mid[1], mid[2]);
      } else {
        // Rotate so the pattern starts at edge e0 (one split) or e0, e1 (two splits).
        int r = 0;
        if (splits == 1) {
          while (mid[r] == 0) ++r;
        } else {
          while (!(mid[r] != 0 && mid[(r + 1) % 3] != 0)) ++r;
        }
        const VertexIndex v0 = f[r], v1 = f[(r + 1) % 3], v2 = f[(r + 2) % 3];
        const VertexIndex m01 = mid[r], m12 = mid[(r + 1) % 3];
        if (splits == 1) {
          emit(v0, m01, v2);
          emit(m01, v1, v2);
        } else {
          emit(m01, v1, m12);
          const std::vector<Vec3>& p = m.positions;
          if (squared_norm(p[v0] - p[m12]) <= squared_norm(p[m01] - p[v2])) {
            emit(v0, m01, m12);
            emit(v0, m12, v2);
          } else {
            emit(v0, m01, v2);
            emit(m01, m12, v2);
          }
        }
      }
    }
    if (faces.size() > max_faces) {
      throw UsageError(
          "refinement to edges <= l would exceed " + std::to_string(max_faces) +
          " faces (VisibilityOptions::max_refined_faces; a coarser resolution makes the edge limit longer)");
    }
    m.faces = std::move(faces);
    refined->input_face = std::move(parents);
    ++refined->rounds;
  }
}

}  // namespace visimp
