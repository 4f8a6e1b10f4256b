// visimp's rasterized V against the Embree ray-cast reference (tests/reference), at reduced
// settings; bench_visibility --reference runs the full ones (1026 cameras, 1024²).
#include "raycast_visibility.h"

#include <gtest/gtest.h>

#include <fstream>

#include "test_meshes.h"
#include "visimp/io/mesh_io.h"
#include "visimp/visibility/visibility.h"

namespace visimp {
namespace {

reference::RaycastVisibility reference_of(const Mesh& mesh, int resolution = 512) {
  reference::RaycastOptions options;
  options.resolution = resolution;
  options.max_edge_fraction = 0.012;
  return reference::raycast_visibility(mesh, octahedron_cameras(2), options);
}

TEST(RaycastReference, KnowsTheKnownAnswers) {
  // The reference must be right on its own before it can judge: convex → 1, sealed → 0.
  const Mesh sphere = test::icosphere(3);
  const auto convex = reference_of(sphere, 256);
  for (float v : convex.face) ASSERT_NEAR(v, 1.0, 0.01);
  Mesh box = test::subdivided_cube(4);
  for (Vec3& p : box.positions) p = p * 4.0 - Vec3{2, 2, 2};
  const std::size_t sphere_first = box.num_faces();
  const auto offset = static_cast<VertexIndex>(box.num_vertices());
  box.positions.insert(box.positions.end(), sphere.positions.begin(), sphere.positions.end());
  for (const Face& f : sphere.faces) box.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  const auto sealed = reference_of(box, 256);
  for (std::size_t f = sphere_first; f < box.num_faces(); ++f) ASSERT_EQ(sealed.face[f], 0.0f);
  for (std::size_t f = 0; f < sphere_first; ++f) ASSERT_GT(sealed.face[f], 0.99f);
}

TEST(RaycastReference, VisimpAgreesOnScansAndCadParts) {
  // The bounds, held at 66 cameras (both sides) and 480² / 512².
  std::vector<std::string> paths = {test::bundled_mesh("bunny.ply"), test::bundled_mesh("kicad_esp_wroom02.ply")};
  for (const char* name : {"kicad_cap_snapin_d40.ply", "kicad_dsub62_male.ply"}) {
    const std::string path = test::shared_mesh(name);
    if (std::ifstream(path))
      paths.push_back(path);
    else
      std::cout << "[ note ] " << path << " is absent (../shared/meshes): not compared\n";
  }
  const auto renderer = make_raster_renderer({480, 0});
  for (const std::string& path : paths) {
    const Mesh mesh = read_mesh(path);
    const Visibility v = compute_visibility(mesh, octahedron_cameras(2), *renderer);
    const auto ref = reference_of(mesh);
    const auto a = reference::compare_visibility(mesh, v.face, ref);
    EXPECT_LE(a.mean_abs_difference, 0.05) << path;
    EXPECT_LE(std::abs(a.mesh_difference), 0.04) << path;
    EXPECT_GE(a.hidden_area_low, 0.98) << path;
    std::cout << "[ data ] " << path << ": V(M) " << v.mesh << " vs " << ref.mesh << ", mean |dV| "
              << a.mean_abs_difference << ", reference-hidden area at V <= 0.02: " << a.hidden_area_low << "\n";
  }
}

}  // namespace
}  // namespace visimp
