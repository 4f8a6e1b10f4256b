// Orientation patches by breadth-first propagation over manifold edges (see orientation.h).
#include "visimp/core/orientation.h"

#include <algorithm>

#include "visimp/core/bounding_box.h"

namespace visimp {
namespace {

struct DirectedEdge {
  std::uint64_t key;     // (min << 32) | max
  std::uint32_t face;
  bool forward;          // the face runs the edge from min to max
  bool operator<(const DirectedEdge& o) const { return key < o.key || (key == o.key && face < o.face); }
};

bool has_repeated_index(const Face& f) { return f[0] == f[1] || f[1] == f[2] || f[0] == f[2]; }

}  // namespace

Face canonical_face(const Face& face, bool reversed) {
  Face f = reversed ? Face{face[0], face[2], face[1]} : face;
  const int first = f[0] <= f[1] && f[0] <= f[2] ? 0 : (f[1] <= f[2] ? 1 : 2);
  return {f[first], f[(first + 1) % 3], f[(first + 2) % 3]};
}

OrientationPatches orientation_patches(const Mesh& mesh) {
  const std::size_t nf = mesh.num_faces();
  std::vector<DirectedEdge> edges;
  edges.reserve(nf * 3);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const Face& face = mesh.faces[f];
    if (has_repeated_index(face)) continue;
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = face[k], b = face[(k + 1) % 3];
      const std::uint64_t lo = std::min(a, b), hi = std::max(a, b);
      edges.push_back({(lo << 32) | hi, f, a < b});
    }
  }
  std::sort(edges.begin(), edges.end());

  // Adjacency across manifold edges, in CSR form; `same` = both faces run the edge the same
  // way, so one of them must be reversed to agree with the other.
  struct Link {
    std::uint32_t face;
    bool same;
  };
  std::vector<std::uint32_t> degree(nf + 1, 0);
  std::vector<std::uint8_t> on_open_edge(nf, 0);  // boundary or non-manifold edge
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 2 && edges[i].face != edges[i + 1].face) {
      ++degree[edges[i].face];
      ++degree[edges[i + 1].face];
    } else {
      for (std::size_t k = i; k < j; ++k) on_open_edge[edges[k].face] = 1;
    }
    i = j;
  }
  std::vector<std::uint32_t> offset(nf + 1, 0);
  for (std::size_t f = 0; f < nf; ++f) offset[f + 1] = offset[f] + degree[f];
  std::vector<Link> links(offset[nf]);
  std::fill(degree.begin(), degree.end(), 0);
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].key == edges[i].key) ++j;
    if (j - i == 2 && edges[i].face != edges[i + 1].face) {
      const bool same = edges[i].forward == edges[i + 1].forward;
      const std::uint32_t a = edges[i].face, b = edges[i + 1].face;
      links[offset[a] + degree[a]++] = {b, same};
      links[offset[b] + degree[b]++] = {a, same};
    }
    i = j;
  }

  OrientationPatches out;
  constexpr std::uint32_t kNone = 0xffffffffu;
  out.patch_of_face.assign(nf, kNone);
  out.reversed.assign(nf, 0);
  const Vec3 center = bounding_box(mesh).center();
  std::vector<std::uint32_t> queue;
  std::vector<std::uint32_t> members;
  for (std::uint32_t seed = 0; seed < nf; ++seed) {
    if (out.patch_of_face[seed] != kNone) continue;
    const std::uint32_t patch = static_cast<std::uint32_t>(out.closed.size());
    bool closed = !has_repeated_index(mesh.faces[seed]);
    queue.assign(1, seed);
    members.clear();
    out.patch_of_face[seed] = patch;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t f = queue[head];
      members.push_back(f);
      closed = closed && !on_open_edge[f];
      for (std::uint32_t l = offset[f]; l < offset[f + 1]; ++l) {
        const Link& link = links[l];
        const std::uint8_t want = out.reversed[f] ^ static_cast<std::uint8_t>(link.same);
        if (out.patch_of_face[link.face] == kNone) {
          out.patch_of_face[link.face] = patch;
          out.reversed[link.face] = want;
          queue.push_back(link.face);
        } else if (out.reversed[link.face] != want) {
          closed = false;  // not orientable: some edge stays misoriented whatever we do
        }
      }
    }
    // Signed volume about the box centre (6× the tetrahedra's): positive when wound outward.
    double volume = 0;
    for (std::uint32_t f : members) {
      const Face c = canonical_face(mesh.faces[f], out.reversed[f] != 0);
      const Vec3 a = mesh.positions[c[0]] - center, b = mesh.positions[c[1]] - center,
                 d = mesh.positions[c[2]] - center;
      volume += dot(a, cross(b, d));
    }
    if (volume < 0) {
      for (std::uint32_t f : members) out.reversed[f] ^= 1;
      volume = -volume;
    }
    out.closed.push_back(closed ? 1 : 0);
    out.signed_volume.push_back(volume / 6);
  }
  return out;
}

}  // namespace visimp
