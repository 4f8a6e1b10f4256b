// Error-report benchmark, two pairs, each in one run with its peers:
//  1. the goal pair: the dragon simplified to 235k faces against a 2.35k-face
//     simplification of that, at Metro's default sampling (10 x the larger face count per
//     direction); visimp metro against CGAL's approximate_Hausdorff_distance at the same sample
//     density, and the sampled Hausdorff against the certified bounds (bounded_hausdorff at
//     0.05%) — the goal: within 0.1% of the bounded reference;
//  2. the full dragon against its 1% simplification, the same comparison, and the image
//     error (20 views) on that pair.
// Every method runs in a forked child (child_process.h) for its own CPU time and peak memory.
//
// usage: bench_metrics [MESH.ply]   (default: ../shared/meshes/dragon.ply)
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <cstdio>
#include <string>

#include "bench_main.h"
#include "child_process.h"
#include "visimp/core/bounding_box.h"
#include "visimp/io/mesh_io.h"
#include "visimp/metrics/bounded_hausdorff.h"
#include "visimp/metrics/image_error.h"
#include "visimp/metrics/surface_distance.h"
#include "visimp/simplify/simplify.h"

namespace {

using visimp::Mesh;
using K = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh to_cgal(const Mesh& m) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> v;
  for (const visimp::Vec3& p : m.positions) v.push_back(sm.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (const visimp::Face& f : m.faces) sm.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return sm;
}

Mesh simplified(const Mesh& m, std::size_t faces) {
  visimp::SimplifyOptions o;
  o.target_faces = faces;
  return visimp::simplify(m, o).mesh;
}

// Prints the table rows for one pair; returns visimp's wall seconds.
void compare(const char* label, const Mesh& a, const Mesh& b, bool with_bound, bool with_image) {
  const std::size_t samples = 10 * std::max(a.num_faces(), b.num_faces());
  const double diagonal = visimp::bounding_box(a).diagonal();
  const bench::ChildResult ours = bench::run_in_child(2, [&] {
    const visimp::SurfaceDistance d = visimp::surface_distance(a, b);
    return std::vector<double>{d.hausdorff, d.rms};
  });
  const bench::ChildResult cgal = bench::run_in_child(1, [&] {
    const SurfaceMesh ca = to_cgal(a), cb = to_cgal(b);
    const double per_area_a = double(samples) / PMP::area(ca), per_area_b = double(samples) / PMP::area(cb);
    return std::vector<double>{std::max(PMP::approximate_Hausdorff_distance<CGAL::Parallel_if_available_tag>(
                                            ca, cb, PMP::parameters::number_of_points_per_area_unit(per_area_a)),
                                        PMP::approximate_Hausdorff_distance<CGAL::Parallel_if_available_tag>(
                                            cb, ca, PMP::parameters::number_of_points_per_area_unit(per_area_b)))};
  });
  std::printf("\n%s: A %zu faces, B %zu faces, %zu face samples per direction, 2 cores\n\n", label, a.num_faces(),
              b.num_faces(), samples);
  std::printf(
      "| method | wall s | CPU s | peak MB | Hausdorff / diag | RMS / diag | wall vs visimp |\n"
      "|---|---|---|---|---|---|---|\n");
  std::printf("| visimp metro | %.2f | %.2f | %.0f | %.5e | %.4e | 1.00 |\n", ours.wall, ours.cpu, ours.peak_mb,
              ours.values[0] / diagonal, ours.values[1] / diagonal);
  std::printf("| CGAL approximate_Hausdorff_distance | %.2f | %.2f | %.0f | %.5e | | %.2f |\n", cgal.wall, cgal.cpu,
              cgal.peak_mb, cgal.values[0] / diagonal, cgal.wall / ours.wall);
  if (with_bound) {
    const double tolerance = 5e-4 * ours.values[0];
    const bench::ChildResult bound = bench::run_in_child(2, [&] {
      const visimp::HausdorffBounds h = visimp::bounded_hausdorff(a, b, tolerance);
      return std::vector<double>{h.lower, h.upper};
    });
    std::printf("| CGAL bounded_error_Hausdorff (0.05%%) | %.2f | %.2f | %.0f | %.5e .. %.5e | | %.2f |\n", bound.wall,
                bound.cpu, bound.peak_mb, bound.values[0] / diagonal, bound.values[1] / diagonal,
                bound.wall / ours.wall);
    // The sampled value can only be low; how far below the certified upper bound is it?
    std::printf("\nvisimp metro's Hausdorff is %.3f%% below the certified upper bound (goal: within 0.1%%)\n",
                100.0 * (bound.values[1] - ours.values[0]) / bound.values[1]);
  }
  if (with_image) {
    const bench::ChildResult image =
        bench::run_in_child(1, [&] { return std::vector<double>{visimp::image_error(a, b).rms_per_pixel}; });
    std::printf(
        "| visimp imgerr (20 views, 256², 4×4 samples a pixel) | %.2f | %.2f | %.0f | per-pixel RMS %.3f of 255 | | "
        "|\n",
        image.wall, image.cpu, image.peak_mb, image.values[0]);
  }
}

}  // namespace

constexpr const char* kUsage =
    "usage: bench_metrics [MESH]   visimp metro vs CGAL's Hausdorff, and the image error (default: the dragon;\n"
    "                              without ../shared/meshes the bundled bunny stands in)\n";

int run(const std::vector<std::string>& args) {
  if (args.size() > 1) throw visimp::UsageError("give at most one mesh (see --help)");
  const std::string path =
      !args.empty() ? args[0] : bench::default_meshes("bench_metrics", {{"dragon.ply", "bunny.ply"}})[0];
  const Mesh dragon = visimp::read_mesh(path);
  const Mesh fine = simplified(dragon, 235000), coarse = simplified(fine, 2350);
  std::printf("mesh: %s (%zu faces)\n", path.c_str(), dragon.num_faces());
  compare("goal pair (235k vs 2.35k; goal: visimp metro <= 1.5 s wall)", fine, coarse, true, false);
  compare("full dragon vs its 1% simplification", dragon, simplified(dragon, dragon.num_faces() / 100), false, true);
  return 0;
}

int main(int argc, char** argv) { return bench::guarded_main("bench_metrics", kUsage, argc, argv, run); }
