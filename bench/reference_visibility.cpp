// Writes a mesh with the ray-cast reference's V (tests/reference) as its face quality, so
// any visimp command that takes --weights-from-quality can run on the independent measure
// (docs/compare.md: VG on the ESP module with visimp's V and with the reference's).
//
// usage: reference_visibility IN OUT [--cameras SET] [--resolution R]
//        defaults: 1026 cameras, 1024² rays, faces refined to ≤ 0.8% of the diameter
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <string>

#include "raycast_visibility.h"
#include "visimp/cameras/camera_set.h"
#include "visimp/io/mesh_io.h"

int main(int argc, char** argv) {
  try {
    std::string in, out, cameras = "1026";
    visimp::reference::RaycastOptions options;
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "--help" || arg == "-h") {
        std::printf("usage: reference_visibility IN OUT [--cameras SET] [--resolution R]\n");
        return 0;
      }
      if (arg == "--cameras" && i + 1 < argc) {
        cameras = argv[++i];
      } else if (arg == "--resolution" && i + 1 < argc) {
        options.resolution = std::atoi(argv[++i]);
      } else if (in.empty()) {
        in = arg;
      } else if (out.empty()) {
        out = arg;
      } else {
        throw std::runtime_error("unexpected argument '" + arg + "'");
      }
    }
    if (out.empty()) throw std::runtime_error("give IN and OUT (--help)");
    if (options.resolution < 16 || options.resolution > 8192) throw std::runtime_error("--resolution must be 16..8192");
    visimp::Mesh mesh = visimp::read_mesh(in);
    const visimp::reference::RaycastVisibility v =
        visimp::reference::raycast_visibility(mesh, visimp::camera_set_from_spec(cameras), options);
    mesh.face_quality = v.face;
    visimp::write_mesh(mesh, out);  // atomic: temp file + rename
    std::printf(
        "{\"input\": \"%s\", \"output\": \"%s\", \"mesh_visibility\": %.6f, \"hidden_area_fraction\": %.6f, "
        "\"refined_faces\": %zu, \"seconds\": %.2f}\n",
        in.c_str(), out.c_str(), v.mesh, v.hidden_area_fraction, v.refined_faces, v.seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reference_visibility: error: %s\n", e.what());
    return 1;
  }
}
