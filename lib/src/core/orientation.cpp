// Orientation patches by breadth-first propagation over manifold edges (see orientation.h).
#include "visimp/core/orientation.h"

#include <algorithm>
#include <cmath>

#include "visimp/core/bounding_box.h"
#include "visimp/core/parallel.h"

namespace visimp {
namespace {

// Members of a patch per run of its volume sum (a patch this small is summed in one run).
constexpr std::size_t kVolumeRun = 1 << 15;

bool has_repeated_index(const Face& f) { return f[0] == f[1] || f[1] == f[2] || f[0] == f[2]; }

}  // namespace

Face canonical_face(const Face& face, bool reversed) {
  Face f = reversed ? Face{face[0], face[2], face[1]} : face;
  const int first = f[0] <= f[1] && f[0] <= f[2] ? 0 : (f[1] <= f[2] ? 1 : 2);
  return {f[first], f[(first + 1) % 3], f[(first + 2) % 3]};
}

OrientationPatches orientation_patches(const Mesh& mesh, unsigned threads) {
  const std::size_t nf = mesh.num_faces();
  // Each edge's corners bucketed by its lower vertex (a counting sort: linear, where sorting
  // all 3·F directed edges took seconds at 14M faces); within a bucket corners ascend.
  // The face runs the edge from its lower vertex v when the corner starting the run is v.
  auto runs_from = [&](std::uint32_t corner, VertexIndex v) { return mesh.faces[corner / 3][corner % 3] == v; };
  std::vector<std::uint32_t> first(mesh.num_vertices() + 1, 0);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const Face& face = mesh.faces[f];
    if (has_repeated_index(face)) continue;
    for (int k = 0; k < 3; ++k) ++first[std::min(face[k], face[(k + 1) % 3]) + 1];
  }
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) first[v + 1] += first[v];
  struct Incidence {
    VertexIndex upper;     // the edge's higher vertex
    std::uint32_t corner;  // face * 3 + k: the corner where the face's run of the edge starts
  };
  std::vector<Incidence> bucketed(first.back());
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t f = 0; f < nf; ++f) {
      const Face& face = mesh.faces[f];
      if (has_repeated_index(face)) continue;
      for (int k = 0; k < 3; ++k) {
        const VertexIndex a = face[k], b = face[(k + 1) % 3];
        bucketed[fill[std::min(a, b)]++] = {std::max(a, b), static_cast<std::uint32_t>(3 * f + k)};
      }
    }
  }

  // Across each manifold edge, the corner of the other face that starts it, with the top
  // bit set when both faces run the edge the same way (one must be reversed to agree).
  // kOpen marks a corner on a boundary or non-manifold edge.
  constexpr std::uint32_t kOpen = 0xffffffffu, kSame = 0x80000000u;
  std::vector<std::uint32_t> across(nf * 3, kOpen);
  // Buckets are independent and each corner lies in one bucket: ranges of vertices in parallel.
  const unsigned workers = worker_count(threads, nf);
  parallel_ranges(mesh.num_vertices(), 1 << 14, workers, [&](std::size_t vbegin, std::size_t vend) {
    for (std::size_t v = vbegin; v < vend; ++v) {
      const auto begin = bucketed.begin() + first[v], end = bucketed.begin() + first[v + 1];
      std::sort(begin, end, [](const Incidence& x, const Incidence& y) {
        return x.upper < y.upper || (x.upper == y.upper && x.corner < y.corner);
      });
      for (auto i = begin; i != end;) {
        auto j = i;
        while (j != end && j->upper == i->upper) ++j;
        if (j - i == 2 && i->corner / 3 != (i + 1)->corner / 3) {
          const auto lower = static_cast<VertexIndex>(v);
          const std::uint32_t same = runs_from(i->corner, lower) == runs_from((i + 1)->corner, lower) ? kSame : 0u;
          across[i->corner] = (i + 1)->corner | same;
          across[(i + 1)->corner] = i->corner | same;
        }
        i = j;
      }
    }
  });
  std::vector<Incidence>().swap(bucketed);  // free before the walk
  std::vector<std::uint32_t>().swap(first);

  OrientationPatches out;
  constexpr std::uint32_t kNone = 0xffffffffu;
  out.patch_of_face.assign(nf, kNone);
  out.reversed.assign(nf, 0);
  const BoundingBox box = bounding_box(mesh);
  const Vec3 center = box.center();
  const double diagonal = box.diagonal();
  std::vector<std::uint32_t> queue;
  std::vector<std::uint32_t> members;
  std::vector<double> run_volume, run_area;
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
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t link = across[3 * f + k];
        if (link == kOpen) {
          closed = false;
          continue;
        }
        const std::uint32_t g = (link & ~kSame) / 3;
        const auto want = static_cast<std::uint8_t>(out.reversed[f] ^ ((link & kSame) != 0 ? 1 : 0));
        if (out.patch_of_face[g] == kNone) {
          out.patch_of_face[g] = patch;
          out.reversed[g] = want;
          queue.push_back(g);
        } else if (out.reversed[g] != want) {
          closed = false;  // not orientable: some edge stays misoriented whatever we do
        }
      }
    }
    // Signed volume about the box centre (6× the tetrahedra's): positive when wound outward.
    // Summed over fixed runs of members in parallel, then the runs' sums in order: the same
    // bits for any thread count.
    const std::size_t runs = (members.size() + kVolumeRun - 1) / kVolumeRun;
    run_volume.assign(runs, 0.0);
    run_area.assign(runs, 0.0);
    parallel_ranges(members.size(), kVolumeRun, workers, [&](std::size_t begin, std::size_t end) {
      double volume = 0, area = 0;
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t f = members[i];
        const Face c = canonical_face(mesh.faces[f], out.reversed[f] != 0);
        const Vec3 a = mesh.positions[c[0]] - center, b = mesh.positions[c[1]] - center,
                   d = mesh.positions[c[2]] - center;
        volume += dot(a, cross(b, d));
        area += norm(cross(b - a, d - a));
      }
      run_volume[begin / kVolumeRun] = volume;
      run_area[begin / kVolumeRun] = area;
    });
    double volume = 0, area = 0;
    for (std::size_t r = 0; r < runs; ++r) {
      volume += run_volume[r];
      area += run_area[r];
    }
    // A closed surface that encloses nothing (a sheet glued to a reversed copy of itself)
    // has no outside to speak of: drawn from both sides like an open one.
    if (!(std::abs(volume) > 1e-9 * area * diagonal)) closed = false;
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
