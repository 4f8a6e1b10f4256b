// The OSMesa backend against the built-in rasterizer: same conventions, same decisions.
#include "visimp/render/osmesa_renderer.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "test_meshes.h"
#include "visimp/io/mesh_io.h"

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
                static_cast<double>(agree) / static_cast<double>(pairs), static_cast<double>(both) / static_cast<double>(either));
    EXPECT_GE(static_cast<double>(agree) / static_cast<double>(pairs), 0.999) << file;
    // Stricter: of the pairs either backend calls visible, nearly all are called so by both.
    EXPECT_GE(static_cast<double>(both) / static_cast<double>(either), 0.995) << file;
  }
}

}  // namespace
}  // namespace visimp
