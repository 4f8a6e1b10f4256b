#include "visimp/core/mesh_stats.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "visimp/core/union_find.h"

namespace visimp {

bool is_degenerate(const Mesh& mesh, const Face& f) { return is_degenerate(mesh.positions, f); }

bool is_degenerate(const std::vector<Vec3>& positions, const Face& f) {
  if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return true;
  return is_degenerate_triangle(positions[f[0]], positions[f[1]], positions[f[2]]);
}

bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  return is_degenerate_triangle(a, b, c, norm(cross(b - a, c - a)));
}

namespace {

struct HalfEdgeKey {
  std::uint64_t key;     // (min << 32) | max
  std::uint32_t corner;  // face * 3 + k, the corner where the directed edge starts
  bool forward;          // start < end
  bool operator<(const HalfEdgeKey& o) const { return key < o.key || (key == o.key && corner < o.corner); }
};

// The items `each(emit)` emits, grouped by `group(item)` (< groups) in group order and each
// group sorted by `<`: the order a full sort gives when the group leads the order. `each` runs
// twice, to count and to place, so the items are laid out once without a second array; the
// sorts are one per group, a handful of items for a vertex. (A full sort of a 14M-face mesh's
// 42M half-edges took 1.5 s.)
template <class T, class Each, class Group>
std::vector<T> grouped_in_order(std::size_t groups, const Each& each, const Group& group) {
  // next[g]: where group g's next item goes; once all are placed, where group g ends.
  std::vector<std::size_t> next(groups + 1, 0);
  each([&](const T& item) { ++next[group(item) + 1]; });
  for (std::size_t g = 0; g < groups; ++g) next[g + 1] += next[g];
  std::vector<T> items(next[groups]);
  each([&](const T& item) { items[next[group(item)]++] = item; });
  for (std::size_t g = 0, begin = 0; g < groups; begin = next[g++])
    std::sort(items.begin() + std::ptrdiff_t(begin), items.begin() + std::ptrdiff_t(next[g]));
  return items;
}

// A face's area; none for a degenerate one (adding 0 leaves a sum's bits as skipping it would).
double face_area(const Mesh& mesh, const Face& face, bool degenerate) {
  return degenerate ? 0.0 : 0.5 * norm(face_normal_unnormalized(mesh, face));
}

}  // namespace

double surface_area(const Mesh& mesh) {
  double area = 0;
  for (const Face& face : mesh.faces) area += face_area(mesh, face, is_degenerate(mesh, face));
  return area;
}

MeshStats analyze(const Mesh& mesh) {
  MeshStats s;
  s.vertices = mesh.num_vertices();
  s.faces = mesh.num_faces();
  s.bbox = bounding_box(mesh);
  const std::size_t nf = mesh.faces.size();

  std::vector<char> referenced(s.vertices, 0);
  UnionFind vertex_sets(s.vertices);
  for (std::size_t f = 0; f < nf; ++f) {
    const Face& face = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      referenced[face[k]] = 1;
      vertex_sets.unite(face[k], face[(k + 1) % 3]);
    }
    const bool degenerate = is_degenerate(mesh, face);
    s.degenerate_faces += degenerate;
    s.area += face_area(mesh, face, degenerate);
  }
  // Half-edges in (edge, corner) order, grouped by their lower vertex.
  std::vector<HalfEdgeKey> half_edges = grouped_in_order<HalfEdgeKey>(
      s.vertices,
      [&mesh, nf](auto&& emit) {
        for (std::size_t f = 0; f < nf; ++f) {
          const Face& face = mesh.faces[f];
          for (int k = 0; k < 3; ++k) {
            const VertexIndex a = face[k], b = face[(k + 1) % 3];
            if (a == b) continue;
            const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
            emit(HalfEdgeKey{(lo << 32) | hi, static_cast<std::uint32_t>(f * 3 + k), a < b});
          }
        }
      },
      [](const HalfEdgeKey& h) { return static_cast<std::size_t>(h.key >> 32); });

  // Corners around one vertex are joined across manifold edges; a vertex whose corners
  // fall into more than one set has several fans (a non-manifold "bow tie" vertex).
  UnionFind corner_sets(nf * 3);
  auto corner_of = [&mesh](std::uint32_t face, VertexIndex v) {
    const Face& f = mesh.faces[face];
    return face * 3 + (f[0] == v ? 0u : (f[1] == v ? 1u : 2u));
  };
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i;
    while (j < half_edges.size() && half_edges[j].key == half_edges[i].key) ++j;
    const std::size_t count = j - i;
    ++s.edges;
    if (count == 1)
      ++s.boundary_edges;
    else if (count > 2)
      ++s.non_manifold_edges;
    else {
      if (half_edges[i].forward == half_edges[i + 1].forward) ++s.misoriented_edges;
      const std::uint32_t f0 = half_edges[i].corner / 3, f1 = half_edges[i + 1].corner / 3;
      const VertexIndex lo = static_cast<VertexIndex>(half_edges[i].key >> 32);
      const VertexIndex hi = static_cast<VertexIndex>(half_edges[i].key & 0xffffffffu);
      corner_sets.unite(corner_of(f0, lo), corner_of(f1, lo));
      corner_sets.unite(corner_of(f0, hi), corner_of(f1, hi));
    }
    i = j;
  }
  std::vector<HalfEdgeKey>().swap(half_edges);  // 48 bytes a face: gone before the face triples

  // Count fans per vertex: distinct corner-set roots among the vertex's corners.
  std::vector<std::uint32_t> first_root(s.vertices, UINT32_MAX);
  std::vector<char> flagged(s.vertices, 0);
  for (std::uint32_t c = 0; c < nf * 3; ++c) {
    const VertexIndex v = mesh.faces[c / 3][c % 3];
    const std::uint32_t root = corner_sets.find(c);
    if (first_root[v] == UINT32_MAX)
      first_root[v] = root;
    else if (first_root[v] != root && !flagged[v]) {
      // A repeated index inside one face gives that vertex two corners of the same face;
      // they count as one fan only if joined, which is the honest answer for such a face.
      flagged[v] = 1;
      ++s.non_manifold_vertices;
    }
  }

  std::vector<char> is_root(s.vertices, 0);
  for (std::size_t v = 0; v < s.vertices; ++v) {
    if (!referenced[v]) {
      ++s.isolated_vertices;
      continue;
    }
    const std::uint32_t r = vertex_sets.find(static_cast<std::uint32_t>(v));
    if (!is_root[r]) {
      is_root[r] = 1;
      ++s.components;
    }
  }

  // Faces as sorted corner triples, in order, grouped by their smallest corner.
  using Triple = std::array<VertexIndex, 3>;
  const std::vector<Triple> sorted = grouped_in_order<Triple>(
      s.vertices,
      [&mesh](auto&& emit) {
        for (const Face& face : mesh.faces) {
          Triple t{face[0], face[1], face[2]};
          std::sort(t.begin(), t.end());
          emit(t);
        }
      },
      [](const Triple& t) { return static_cast<std::size_t>(t[0]); });
  for (std::size_t i = 1; i < sorted.size(); ++i) s.duplicate_faces += (sorted[i] == sorted[i - 1]);
  return s;
}

}  // namespace visimp
