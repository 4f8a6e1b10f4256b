#include "visimp/metrics/image_error.h"

#include <gtest/gtest.h>

#include "test_meshes.h"
#include "visimp/io/mesh_io.h"
#include "visimp/simplify/simplify.h"

namespace visimp {
namespace {

TEST(ImageError, MeshAgainstItselfIsZero) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  const ImageError e = image_error(bunny, bunny, {128, 2, ""});
  EXPECT_EQ(e.views, 20u);
  EXPECT_EQ(e.rms, 0.0);
  EXPECT_EQ(e.rms_per_pixel, 0.0);
}

TEST(ImageError, GrowsAsTheMeshIsSimplifiedFurther) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  double previous = 0;
  for (double ratio : {0.5, 0.2, 0.05, 0.01}) {
    SimplifyOptions o;
    o.target_ratio = ratio;
    const ImageError e = image_error(bunny, simplify(bunny, o).mesh, {256, 2, ""});
    EXPECT_GT(e.rms, previous) << "ratio " << ratio;
    // eq. 5.11 and the per-pixel RMS measure the same images.
    EXPECT_NEAR(e.rms_per_pixel, e.rms / std::sqrt(20.0 * 256 * 256), 1e-9);
    previous = e.rms;
  }
}

}  // namespace
}  // namespace visimp
