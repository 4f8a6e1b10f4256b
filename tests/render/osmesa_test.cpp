// The OSMesa backend against the built-in rasterizer: same conventions, same decisions.
#include "visimp/render/osmesa_renderer.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "test_meshes.h"
#include "visimp/io/mesh_io.h"
#include "visimp/visibility/visibility.h"

namespace visimp {
namespace {

// Per camera, which faces own at least one pixel.
class OwnershipRecorder final : public FrameConsumer {
 public:
  OwnershipRecorder(std::size_t cameras, std::size_t faces) : owned_(cameras, std::vector<bool>(faces, false)) {}
  void begin(unsigned) override {}
  void consume(const Frame& frame, std::size_t camera, unsigned) override {
    for (std::uint32_t id : frame.ids)
      if (id != 0) owned_[camera][id - 1] = true;
  }
  const std::vector<std::vector<bool>>& owned() const { return owned_; }

 private:
  std::vector<std::vector<bool>> owned_;
};

TEST(Osmesa, AgreesWithTheRasterizerOnRealMeshes) {
  const CameraSet cameras = octahedron_cameras(2);
  for (const char* file : {"bunny.ply", "fandisk_cad.ply", "kicad_esp_wroom02.ply"}) {
    const Mesh mesh = read_mesh(test::bundled_mesh(file));
    const RenderScene scene = RenderScene::from_mesh(mesh, false);
    OwnershipRecorder raster(cameras.size(), mesh.num_faces()), gl(cameras.size(), mesh.num_faces());
    make_raster_renderer({320, 2})->render(scene, cameras, 0, cameras.size(), raster);
    make_osmesa_renderer({320, 2})->render(scene, cameras, 0, cameras.size(), gl);
    std::size_t pairs = 0, agree = 0, either = 0, both = 0;
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
        const bool a = raster.owned()[c][f], b = gl.owned()[c][f];
        ++pairs;
        agree += a == b ? 1 : 0;
        either += (a || b) ? 1 : 0;
        both += (a && b) ? 1 : 0;
      }
    }
    std::printf("%s: %.6f of (face, camera) pairs agree; %.6f of the visible ones\n", file,
                static_cast<double>(agree) / static_cast<double>(pairs),
                static_cast<double>(both) / static_cast<double>(either));
    EXPECT_GE(static_cast<double>(agree) / static_cast<double>(pairs), 0.999) << file;
    // Stricter: of the pairs either backend calls visible, nearly all are called so by both.
    EXPECT_GE(static_cast<double>(both) / static_cast<double>(either), 0.995) << file;
  }
}

TEST(Osmesa, CullsOnlyTheClosedSurfacesAsTheRasterizerDoes) {
  // The bunny (closed: culled) beside an open sheet (drawn from both sides): the scene's
  // first faces are culled, the rest not, in both backends.
  Mesh scene = read_mesh(test::bundled_mesh("bunny.ply"));
  const Mesh sheet = test::grid(6);
  const auto offset = static_cast<VertexIndex>(scene.num_vertices());
  for (const Vec3& p : sheet.positions) scene.positions.push_back(p * 0.05 + Vec3{0.4, -0.2, 0});
  for (const Face& f : sheet.faces) scene.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  const CameraSet cameras = octahedron_cameras(2);
  const auto raster = make_raster_renderer({200, 2});
  const auto gl = make_osmesa_renderer({200, 2});
  const Visibility a = compute_visibility(scene, cameras, *raster), b = compute_visibility(scene, cameras, *gl);
  EXPECT_EQ(a.stats.two_sided_faces, sheet.num_faces());
  EXPECT_NEAR(a.mesh, b.mesh, 0.005);
  double differ = 0;
  for (std::size_t f = 0; f < scene.num_faces(); ++f) differ += std::abs(a.face[f] - b.face[f]);
  EXPECT_LT(differ / static_cast<double>(scene.num_faces()), 0.01);
}

}  // namespace
}  // namespace visimp
