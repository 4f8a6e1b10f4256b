// Uses the installed visimp: a cube's visibility (convex: V = 1 everywhere), then a mesh read,
// its visibility and a VG-style simplification. Prints "V(cube) V(mesh) faces_out"; exit 0 only
// when the numbers are right.
#include <cmath>
#include <cstdio>
#include <exception>

#include "visimp/cameras/camera_set.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/renderer.h"
#include "visimp/simplify/simplify.h"
#include "visimp/visibility/visibility.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: consumer MESH\n");
    return 2;
  }
  try {
    visimp::Mesh cube;
    for (int i = 0; i < 8; ++i) cube.positions.push_back({double(i & 1), double(i >> 1 & 1), double(i >> 2 & 1)});
    cube.faces = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                  {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
    const visimp::CameraSet cameras = visimp::octahedron_cameras(1);
    visimp::RenderOptions render;
    render.resolution = 128;
    render.threads = 1;
    auto renderer = visimp::make_raster_renderer(render);
    const visimp::Visibility cube_v = visimp::compute_visibility(cube, cameras, *renderer);

    const visimp::Mesh mesh = visimp::read_mesh(argv[1]);
    const visimp::Visibility mesh_v = visimp::compute_visibility(mesh, cameras, *renderer);
    visimp::SimplifyOptions options;
    options.target_ratio = 0.25;
    const visimp::Simplified simplified = visimp::simplify(mesh, options);
    std::printf("%.4f %.4f %zu\n", cube_v.mesh, mesh_v.mesh, simplified.mesh.num_faces());
    const bool ok = std::abs(cube_v.mesh - 1) < 1e-6 && mesh_v.mesh > 0.5 && mesh_v.mesh <= 1 &&
                    simplified.mesh.num_faces() <= mesh.num_faces() / 4 + 1 && simplified.mesh.num_faces() > 0;
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
