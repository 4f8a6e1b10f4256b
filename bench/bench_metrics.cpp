// Error-report benchmark: visimp metro against CGAL's approximate_Hausdorff_distance at an
// equal number of face samples, on a mesh and its 1% simplification, in one run; and the
// image error (20 views) on the same pair. Each in a forked child (child_process.h).
//
// usage: bench_metrics [MESH.ply]   (default: ../shared/meshes/dragon.ply)
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <cstdio>
#include <string>

#include "child_process.h"
#include "visimp/core/bounding_box.h"
#include "visimp/io/mesh_io.h"
#include "visimp/metrics/image_error.h"
#include "visimp/metrics/surface_distance.h"
#include "visimp/simplify/simplify.h"

namespace {

using visimp::Mesh;
using K = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<K::Point_3>;

SurfaceMesh to_cgal(const Mesh& m) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> v;
  for (const visimp::Vec3& p : m.positions) v.push_back(sm.add_vertex(K::Point_3(p.x, p.y, p.z)));
  for (const visimp::Face& f : m.faces) sm.add_face(v[f[0]], v[f[1]], v[f[2]]);
  return sm;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : std::string(VISIMP_SHARED_MESHES_DIR) + "/dragon.ply";
  const Mesh a = visimp::read_mesh(path);
  visimp::SimplifyOptions o;
  o.target_ratio = 0.01;
  const Mesh b = visimp::simplify(a, o).mesh;
  const std::size_t samples = 10 * a.num_faces();  // Metro's default budget per direction

  const bench::ChildResult ours = bench::run_in_child(2, [&] {
    const visimp::SurfaceDistance d = visimp::surface_distance(a, b);
    return std::vector<double>{d.hausdorff / d.diagonal, d.rms / d.diagonal};
  });
  const bench::ChildResult cgal = bench::run_in_child(1, [&] {
    const SurfaceMesh ca = to_cgal(a), cb = to_cgal(b);
    const double area = CGAL::Polygon_mesh_processing::area(ca);
    const double per_area = double(samples) / area;
    namespace PMP = CGAL::Polygon_mesh_processing;
    const double h = std::max(
        PMP::approximate_Hausdorff_distance<CGAL::Parallel_if_available_tag>(ca, cb, PMP::parameters::number_of_points_per_area_unit(per_area)),
        PMP::approximate_Hausdorff_distance<CGAL::Parallel_if_available_tag>(cb, ca, PMP::parameters::number_of_points_per_area_unit(per_area)));
    return std::vector<double>{h};
  });
  const bench::ChildResult image = bench::run_in_child(1, [&] {
    return std::vector<double>{visimp::image_error(a, b).rms_per_pixel};
  });
  const double diagonal = [&] {
    visimp::BoundingBox box = visimp::bounding_box(a);
    return box.diagonal();
  }();
  std::printf("pair: %s (%zu faces) vs its 1%% simplification (%zu faces), %zu face samples per direction, 2 cores\n\n",
              path.c_str(), a.num_faces(), b.num_faces(), samples);
  std::printf("| method | wall s | CPU s | peak MB | Hausdorff / diag | RMS / diag | wall vs visimp |\n|---|---|---|---|---|---|---|\n");
  std::printf("| visimp metro | %.2f | %.2f | %.0f | %.4e | %.4e | 1.00 |\n", ours.wall, ours.cpu, ours.peak_mb,
              ours.values[0], ours.values[1]);
  std::printf("| CGAL approximate_Hausdorff_distance | %.2f | %.2f | %.0f | %.4e | | %.2f |\n", cgal.wall, cgal.cpu,
              cgal.peak_mb, cgal.values[0] / diagonal, cgal.wall / ours.wall);
  std::printf("| visimp imgerr (20 views, 256²) | %.2f | %.2f | %.0f | per-pixel RMS %.3f of 255 | | |\n", image.wall,
              image.cpu, image.peak_mb, image.values[0]);
  return 0;
}
