// Patch creation by smallest-first fusion (see patch_partition.h).
//
// Cost: a binary heap of (area, patch) with stale entries skipped, a parent forest for the
// fused patches, and per patch a neighbour list that may hold stale ids (patches fused
// since) until the patch is popped and its list is mapped to current patches and
// deduplicated. Fusing appends the shorter list to the longer one, so every id is copied
// O(log n) times: a million faces fuse to 1000 patches in about a second.
#include "visimp/patches/patch_partition.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>
#include <tuple>

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/union_find.h"

namespace visimp {
namespace {

struct Edge {
  VertexIndex a, b;
  std::uint32_t face;
  bool operator<(const Edge& o) const { return std::tie(a, b, face) < std::tie(o.a, o.b, o.face); }
};

}  // namespace

std::vector<std::vector<std::uint32_t>> face_neighbours(const Mesh& mesh) {
  std::vector<Edge> edges;
  edges.reserve(mesh.num_faces() * 3);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Face& face = mesh.faces[f];
    for (int k = 0; k < 3; ++k) {
      VertexIndex a = face[k], b = face[(k + 1) % 3];
      if (a == b) continue;  // a collapsed edge joins nothing
      if (a > b) std::swap(a, b);
      edges.push_back({a, b, static_cast<std::uint32_t>(f)});
    }
  }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<std::uint32_t>> neighbours(mesh.num_faces());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].a == edges[i].a && edges[j].b == edges[i].b) ++j;
    // Around a non-manifold edge all faces are mutual neighbours; around a pathological one
    // (more than 16 faces) a star through the first keeps the lists linear in size.
    const bool star = j - i > 16;
    for (std::size_t p = i; p < j; ++p) {
      for (std::size_t q = i; q < (star ? i + 1 : j); ++q) {
        if (edges[p].face == edges[q].face) continue;
        neighbours[edges[p].face].push_back(edges[q].face);
        if (star) neighbours[edges[q].face].push_back(edges[p].face);
      }
    }
    i = j;
  }
  return neighbours;
}

namespace {

BoundingBox face_box(const Mesh& mesh, const Face& f) {
  BoundingBox box;
  for (VertexIndex v : f) box.extend(mesh.positions[v]);
  return box;
}

BoundingBox united(const BoundingBox& a, const BoundingBox& b) {
  BoundingBox box = a;
  if (!b.empty()) {
    box.extend(b.min);
    box.extend(b.max);
  }
  return box;
}

struct HeapEntry {
  double area;
  std::uint32_t patch, stamp;
  // std::priority_queue pops the largest: invert so the smallest area (then id) comes first.
  bool operator<(const HeapEntry& o) const { return std::tie(area, patch) > std::tie(o.area, o.patch); }
};

}  // namespace

std::vector<OptionSpec> describe_options(PatchOptions& options) {
  return {
      option_spec("--patches", "N", options.count,
                  "patch count to stop at; 0 = only --max-patch-diagonal limits fusion"),
      option_spec("--max-patch-diagonal", "D", options.max_diagonal,
                  "never fuse into a patch whose bounding-box diagonal exceeds D (input units; 0 = no limit)"),
  };
}

void check_options(const PatchOptions& options) {
  if (!(options.max_diagonal >= 0) || !std::isfinite(options.max_diagonal)) {
    throw OptionError(&options.max_diagonal, "PatchOptions::max_diagonal", "must be a finite number >= 0");
  }
  if (options.count == 0 && options.max_diagonal == 0) {
    throw OptionError(nullptr, "PatchOptions", "needs a count or a max_diagonal");
  }
  if (options.count > 0xffffffffu) throw OptionError(&options.count, "PatchOptions::count", "must be below 2^32");
}

PatchPartition build_patches(const Mesh& mesh, const PatchOptions& options) {
  check_options(options);
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = mesh.num_faces();
  PatchPartition result;
  std::vector<std::vector<std::uint32_t>> neighbours = face_neighbours(mesh);
  {
    UnionFind components(n);
    for (std::uint32_t f = 0; f < n; ++f) {
      for (std::uint32_t g : neighbours[f]) components.unite(f, g);
    }
    for (std::uint32_t f = 0; f < n; ++f) result.components += components.find(f) == f;
  }

  std::vector<std::uint32_t> parent(n), stamp(n, 0);
  std::vector<BoundingBox> box(n);
  std::vector<double> area(n);
  std::priority_queue<HeapEntry> heap;
  for (std::uint32_t f = 0; f < n; ++f) {
    parent[f] = f;
    box[f] = face_box(mesh, mesh.faces[f]);
    area[f] = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    heap.push({area[f], f, 0});
  }
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };

  const std::size_t target = options.count == 0 ? 1 : options.count;
  std::size_t live = n;
  while (live > target && !heap.empty()) {
    const HeapEntry top = heap.top();
    heap.pop();
    const std::uint32_t p = top.patch;
    if (parent[p] != p || stamp[p] != top.stamp) continue;  // fused or changed since it was pushed

    // The current neighbours of p: stale ids mapped to their patches, p itself and repeats removed.
    std::vector<std::uint32_t>& list = neighbours[p];
    for (std::uint32_t& q : list) q = find(q);
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    list.erase(std::remove(list.begin(), list.end(), p), list.end());
    if (list.empty()) continue;  // a component of its own: it stays as it is

    std::uint32_t best = list.front();
    double best_diagonal = united(box[p], box[best]).diagonal();
    for (std::uint32_t q : list) {
      const double d = united(box[p], box[q]).diagonal();
      if (d < best_diagonal || (d == best_diagonal && box[q].diagonal() < box[best].diagonal())) {
        best = q;
        best_diagonal = d;
      }
    }
    if (options.max_diagonal > 0 && best_diagonal > options.max_diagonal) continue;  // p cannot grow

    // The patch with the longer neighbour list survives, so lists are copied small into large.
    std::uint32_t keep = best, absorbed = p;
    if (neighbours[absorbed].size() > neighbours[keep].size()) std::swap(keep, absorbed);
    parent[absorbed] = keep;
    box[keep] = united(box[keep], box[absorbed]);
    area[keep] += area[absorbed];
    std::vector<std::uint32_t>& into = neighbours[keep];
    into.insert(into.end(), neighbours[absorbed].begin(), neighbours[absorbed].end());
    std::vector<std::uint32_t>().swap(neighbours[absorbed]);
    ++stamp[keep];
    heap.push({area[keep], keep, stamp[keep]});
    --live;
  }

  // Number patches by their lowest face.
  constexpr std::uint32_t kNone = 0xffffffffu;
  std::vector<std::uint32_t> number(n, kNone);
  result.face_patch.resize(n);
  for (std::uint32_t f = 0; f < n; ++f) {
    const std::uint32_t root = find(f);
    if (number[root] == kNone) {
      number[root] = static_cast<std::uint32_t>(result.area.size());
      result.area.push_back(area[root]);
      result.diagonal.push_back(box[root].diagonal());
      result.face_count.push_back(0);
    }
    result.face_patch[f] = number[root];
    ++result.face_count[number[root]];
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

PatchPartition faces_as_patches(const Mesh& mesh) {
  PatchPartition result;
  const std::size_t n = mesh.num_faces();
  result.face_patch.resize(n);
  result.area.resize(n);
  result.diagonal.resize(n);
  result.face_count.assign(n, 1);
  for (std::uint32_t f = 0; f < n; ++f) {
    result.face_patch[f] = f;
    result.area[f] = 0.5 * norm(face_normal_unnormalized(mesh, mesh.faces[f]));
    result.diagonal[f] = face_box(mesh, mesh.faces[f]).diagonal();
  }
  return result;
}

std::vector<std::array<std::uint8_t, 3>> patch_colors(std::size_t patches) {
  std::vector<std::array<std::uint8_t, 3>> colors(patches);
  constexpr double kGolden = 0.618033988749895;
  for (std::size_t i = 0; i < patches; ++i) {
    const double h = std::fmod(static_cast<double>(i) * kGolden, 1.0) * 6.0;
    // Alternate saturation and value a little so hues that come round again still differ.
    const double s = (i % 3 == 0) ? 0.55 : 0.8, v = (i % 2 == 0) ? 0.95 : 0.75;
    const int sector = static_cast<int>(h);
    const double frac = h - sector;
    const double p = v * (1 - s), q = v * (1 - s * frac), t = v * (1 - s * (1 - frac));
    double r = v, g = t, b = p;
    switch (sector) {
      case 1:
        r = q;
        g = v;
        b = p;
        break;
      case 2:
        r = p;
        g = v;
        b = t;
        break;
      case 3:
        r = p;
        g = q;
        b = v;
        break;
      case 4:
        r = t;
        g = p;
        b = v;
        break;
      case 5:
        r = v;
        g = p;
        b = q;
        break;
      default:
        break;
    }
    colors[i] = {static_cast<std::uint8_t>(std::lround(r * 255)), static_cast<std::uint8_t>(std::lround(g * 255)),
                 static_cast<std::uint8_t>(std::lround(b * 255))};
  }
  return colors;
}

}  // namespace visimp
