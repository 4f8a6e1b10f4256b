// Patch bitfields benchmark (issue 7), every figure a ratio against a peer in the same run:
//
//   1. view-reconstruction query time (1000 patches, 1026 samples): the hierarchy lookup +
//      OR of 3 rows + the list of set patches, the same with per-cell rows precomputed, the
//      convex-hull walk on an arbitrary 1026-direction set (6 rows), against the naive
//      selection (scan every camera for the 3 nearest, then OR) — ns per query;
//   2. patch creation on the dragon (871k faces → 1000 patches) against meshoptimizer's
//      meshlet builder (clusters of ≤ 512 triangles: the nearest peer that groups faces);
//   3. .vbf sizes for 50 and 2000 patches × 1026 samples (the paper: 183 KB and 709 KB).
//
// usage: bench_patches [MESH.ply]   (default: ../shared/meshes/dragon.ply)
#include <meshoptimizer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "bench_main.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/io/mesh_io.h"
#include "visimp/patches/bitfield_file.h"
#include "visimp/patches/patch_study.h"
#include "visimp/patches/view_reconstruction.h"

namespace {

using namespace visimp;
using Clock = std::chrono::steady_clock;

template <typename F>
double best_seconds(int repeats, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const auto t = Clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(Clock::now() - t).count());
  }
  return best;
}

BitfieldSet make_set(const Mesh& mesh, const PatchPartition& partition, const CameraSet& cameras, Renderer& renderer) {
  BitfieldSet set = make_bitfield_set(mesh, partition, false, cameras, renderer.resolution(), {});
  set.bits = record_bitfields(mesh, partition, cameras, renderer, {});
  return set;
}

// ns per query of `query(direction)` over the directions, best of 5 passes.
template <typename F>
double ns_per_query(const std::vector<Vec3>& directions, F&& query) {
  std::size_t sink = 0;
  const double s = best_seconds(5, [&] {
    for (const Vec3& d : directions) sink += query(d);
  });
  if (sink == 42) std::puts("");  // keep the work
  return 1e9 * s / static_cast<double>(directions.size());
}

}  // namespace

constexpr const char* kUsage =
    "usage: bench_patches [MESH]   view reconstruction, patch creation vs meshoptimizer, .vbf sizes (default: the\n"
    "                              dragon; without ../shared/meshes the bundled bunny stands in)\n";

int run(const std::vector<std::string>& args) {
  if (args.size() > 1) throw visimp::UsageError("give at most one mesh (see --help)");
  const std::string path =
      !args.empty() ? args[0] : bench::default_meshes("bench_patches", {{"dragon.ply", "bunny.ply"}})[0];
  const Mesh mesh = read_mesh(path);
  std::printf("mesh: %s (%zu faces)\n\n", path.c_str(), mesh.num_faces());
  RenderOptions render;
  render.resolution = 480;
  auto renderer = make_raster_renderer(render);

  // 2. Patch creation against meshoptimizer's meshlets.
  PatchOptions patch_options;
  patch_options.count = 1000;
  PatchPartition patches;
  const double visimp_patch_s = best_seconds(3, [&] { patches = build_patches(mesh, patch_options); });
  std::vector<unsigned> indices;
  indices.reserve(mesh.num_faces() * 3);
  for (const Face& f : mesh.faces) indices.insert(indices.end(), f.begin(), f.end());
  std::vector<float> xyz;
  for (const Vec3& p : mesh.positions) xyz.insert(xyz.end(), {float(p.x), float(p.y), float(p.z)});
  std::size_t meshlets = 0;
  const double meshopt_s = best_seconds(3, [&] {
    const std::size_t max_vertices = 255, max_triangles = 512;
    const std::size_t bound = meshopt_buildMeshletsBound(indices.size(), max_vertices, max_triangles);
    std::vector<meshopt_Meshlet> m(bound);
    std::vector<unsigned> mv(bound * max_vertices);
    std::vector<unsigned char> mt(bound * max_triangles * 3);
    meshlets = meshopt_buildMeshlets(m.data(), mv.data(), mt.data(), indices.data(), indices.size(), xyz.data(),
                                     mesh.num_vertices(), sizeof(float) * 3, max_vertices, max_triangles, 0.0f);
  });
  std::printf("patch creation (best of 3)\n\n| method | clusters | seconds | vs visimp |\n|---|---|---|---|\n");
  std::printf("| visimp build_patches (1000) | %zu | %.3f | 1.00 |\n", patches.patch_count(), visimp_patch_s);
  std::printf("| meshoptimizer buildMeshlets (<= 512 tri, <= 255 vert) | %zu | %.3f | %.2f |\n\n", meshlets, meshopt_s,
              meshopt_s / visimp_patch_s);

  // 1. Query time at 1000 patches × 1026 samples.
  const CameraSet octahedron = octahedron_cameras(4);
  const auto t = Clock::now();
  const BitfieldSet set = make_set(mesh, patches, octahedron, *renderer);
  const double sampling_s = std::chrono::duration<double>(Clock::now() - t).count();
  const std::vector<Vec3> directions = random_directions(100000, 3);
  const ViewReconstructor plain(set), precomputed(set, true);
  std::vector<std::uint64_t> joined(plain.words_per_row());
  std::vector<std::uint32_t> list;
  list.reserve(set.bits.units);
  auto listed = [&](const ViewReconstructor& r, const Vec3& d) {
    r.join(d, joined.data());
    list.clear();
    for_each_set_bit(joined.data(), joined.size(),
                     [&](std::size_t u) { list.push_back(static_cast<std::uint32_t>(u)); });
    return list.size();
  };
  const double hierarchy_ns = ns_per_query(directions, [&](const Vec3& d) { return listed(plain, d); });
  const double precomputed_ns = ns_per_query(directions, [&](const Vec3& d) { return listed(precomputed, d); });
  // The naive peer: the three cameras nearest the direction by a scan, then the same OR and list.
  const double naive_ns = ns_per_query(directions, [&](const Vec3& d) {
    std::array<std::pair<double, std::uint32_t>, 3> best{{{-2, 0}, {-2, 0}, {-2, 0}}};
    for (std::uint32_t c = 0; c < octahedron.size(); ++c) {
      const double cosine = dot(octahedron.directions[c], d);
      if (cosine > best[2].first) {
        best[2] = {cosine, c};
        std::sort(best.begin(), best.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
      }
    }
    std::copy_n(set.bits.row(best[0].second), joined.size(), joined.data());
    for (int k = 1; k < 3; ++k) {
      const std::uint64_t* row = set.bits.row(best[static_cast<std::size_t>(k)].second);
      for (std::size_t w = 0; w < joined.size(); ++w) joined[w] |= row[w];
    }
    list.clear();
    for_each_set_bit(joined.data(), joined.size(),
                     [&](std::size_t u) { list.push_back(static_cast<std::uint32_t>(u)); });
    return list.size();
  });
  // Arbitrary camera set of the same size: convex hull + walk, 6 rows.
  BitfieldSet arbitrary = set;
  arbitrary.cameras = CameraSet{"random-1026", random_directions(1026, 77)};
  arbitrary.bits = record_bitfields(mesh, patches, arbitrary.cameras, *renderer, {});
  const ViewReconstructor hull(arbitrary);
  const double hull_ns = ns_per_query(directions, [&](const Vec3& d) { return listed(hull, d); });
  std::printf(
      "view reconstruction: 1000 patches, 1026 samples (sampling took %.2f s), 100000 random directions,\n"
      "select + OR + list of patches to draw, best of 5\n\n"
      "| method | ns / query | vs visimp hierarchy |\n|---|---|---|\n",
      sampling_s);
  std::printf("| visimp octahedron hierarchy (3 rows) | %.0f | 1.00 |\n", hierarchy_ns);
  std::printf("| visimp hierarchy, rows precomputed per cell | %.0f | %.2f |\n", precomputed_ns,
              precomputed_ns / hierarchy_ns);
  std::printf("| visimp convex hull walk, arbitrary set (6 rows) | %.0f | %.2f |\n", hull_ns, hull_ns / hierarchy_ns);
  std::printf("| naive: scan 1026 cameras for the 3 nearest | %.0f | %.2f |\n\n", naive_ns, naive_ns / hierarchy_ns);
  std::printf("goal: <= 10 us per query -> %s (%.2f us)\n\n", hierarchy_ns <= 10000 ? "met" : "NOT met",
              hierarchy_ns / 1000);

  // 3. File sizes.
  std::printf(
      "file sizes, 1026 samples (paper: 183 KB for 50 patches, 709 KB for 2000)\n\n"
      "| patches | file bytes | bitfield bytes | bitfields uncompressed | patch map bytes |\n|---|---|---|---|---|\n");
  for (std::size_t count : {50u, 2000u}) {
    patch_options.count = count;
    const PatchPartition p = build_patches(mesh, patch_options);
    const BitfieldSet s = make_set(mesh, p, octahedron, *renderer);
    const std::string file = "/tmp/bench_patches.vbf";
    const BitfieldFileSizes sizes = write_bitfield_file(s, file, true);
    std::remove(file.c_str());
    std::printf("| %zu | %llu | %llu | %llu | %llu |\n", count, static_cast<unsigned long long>(sizes.total),
                static_cast<unsigned long long>(sizes.bitfields),
                static_cast<unsigned long long>(sizes.bitfields_uncompressed),
                static_cast<unsigned long long>(sizes.patch_map));
  }
  return 0;
}

int main(int argc, char** argv) { return bench::guarded_main("bench_patches", kUsage, argc, argv, run); }
