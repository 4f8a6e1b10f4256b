#include "visimp/metrics/image_error.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "box_filter.h"
#include "test_meshes.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/frame.h"
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

// A frame that followed B's bounding box would render A a little differently for every B (a
// sub-pixel move changes A's aliasing), so QB and VG results would be measured against
// different images of the same input. The views frame A alone when B fits in them: adding to
// B a zero-area triangle that widens its bounding box (inside A's view sphere) and draws no
// pixel must leave the error exactly as it was.
TEST(ImageError, ViewsFrameTheReferenceWhenTheOtherFitsInIt) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  SimplifyOptions o;
  o.target_ratio = 0.2;
  const Mesh simplified = simplify(bunny, o).mesh;
  const BoundingBox box = bounding_box(bunny);
  Mesh widened = simplified;
  const Vec3 outside{box.max.x + 0.02 * box.diagonal(), box.center().y, box.center().z};
  const auto first = static_cast<VertexIndex>(widened.positions.size());
  widened.positions.insert(widened.positions.end(), {outside, outside, outside});
  widened.faces.push_back({first, first + 1, first + 2});
  ASSERT_GT(bounding_box(widened).max.x, box.max.x);
  for (int supersample : {1, 4}) {
    const ImageError plain = image_error(bunny, simplified, {128, 2, "", supersample});
    EXPECT_GT(plain.rms, 0.0);
    EXPECT_EQ(image_error(bunny, widened, {128, 2, "", supersample}).rms, plain.rms) << supersample;
  }
}

// A shift by a quarter of a pixel changes point-sampled edge pixels by the whole intensity
// step, or not at all; averaged samples change by about a quarter of it. Supersampling is what
// makes the measure follow sub-pixel geometry instead of where pixel centres happen to fall.
TEST(ImageError, SupersamplingMeasuresSubpixelShiftsInProportion) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  const int resolution = 128;
  const double pixel = 2 * view_radius(bounding_box(bunny)) / resolution;
  Mesh shifted = bunny;
  for (Vec3& p : shifted.positions) p = p + Vec3{0.25 * pixel, 0.25 * pixel, 0};
  const ImageError point = image_error(bunny, shifted, {resolution, 2, "", 1});
  const ImageError averaged = image_error(bunny, shifted, {resolution, 2, "", 4});
  EXPECT_EQ(averaged.supersample, 4);
  EXPECT_GT(averaged.rms, 0.0);
  EXPECT_LT(averaged.rms, 0.75 * point.rms);
}

// compare measures every level and tie-noise run against one input: ImageErrorReference draws
// the input's views once. Each error must be image_error's to the bit: for results inside the
// input's sphere (its views reused), for one reaching outside it (the frame widens and the
// input is drawn again), and for an empty input (each result frames the views).
TEST(ImageError, AReferenceDrawnOnceGivesImageErrorsBits) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  std::vector<Mesh> results;
  for (double ratio : {0.3, 0.05}) {
    SimplifyOptions o;
    o.target_ratio = ratio;
    results.push_back(simplify(bunny, o).mesh);
  }
  Mesh moved = results[0];
  const double diagonal = bounding_box(bunny).diagonal();
  for (Vec3& p : moved.positions) p = p + Vec3{0.4 * diagonal, 0, 0};
  results.push_back(moved);
  const ImageErrorOptions options{96, 2, "", 2};
  const ImageErrorReference reference(bunny, options);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const ImageError once = reference.error_to(results[i]), each = image_error(bunny, results[i], options);
    EXPECT_GT(once.rms, 0.0) << i;
    EXPECT_EQ(once.rms, each.rms) << i;
    EXPECT_EQ(once.view_rms, each.view_rms) << i;
  }
  const Mesh empty;
  EXPECT_EQ(ImageErrorReference(empty, options).error_to(bunny).rms, image_error(empty, bunny, options).rms);
  EXPECT_THROW(ImageErrorReference(bunny, {128, 2, "", 9}), UsageError);
}

// Each pixel of a supersampled view sums exactly the s × s samples it covers, background
// samples (id 0) adding nothing. Sample values are multiples of 1/4, so every sum is exact in
// any order and the filter must match a block-by-block sum to the bit; a block shifted by one
// sample, rows mixed up or a background sample counted all change some pixel.
TEST(ImageError, BoxFilterSumsEachPixelsOwnSamples) {
  std::mt19937 random(7);
  auto value = [](std::uint32_t id) { return 0.25 * double(id) + 0.5; };  // nonzero for id 0 too
  for (std::size_t supersample : {1, 2, 3, 4}) {
    const std::size_t size = 7, samples = size * supersample;
    std::vector<std::uint32_t> ids(samples * samples);
    for (std::uint32_t& id : ids) id = random() % 3 == 0 ? 0u : 1u + static_cast<std::uint32_t>(random() % 50);  // a third background
    std::vector<float> image(size * size, 0.0f);
    detail::add_box_filtered(ids.data(), samples, supersample, value, image.data());
    for (std::size_t py = 0; py < size; ++py)
      for (std::size_t px = 0; px < size; ++px) {
        double expected = 0;
        for (std::size_t y = py * supersample; y < (py + 1) * supersample; ++y)
          for (std::size_t x = px * supersample; x < (px + 1) * supersample; ++x)
            if (const std::uint32_t id = ids[y * samples + x]; id != 0) expected += value(id);
        ASSERT_EQ(double(image[py * size + px]), expected) << "s = " << supersample << ", pixel " << px << ", " << py;
      }
  }
}

TEST(ImageError, RejectsABadSupersamplingFactor) {
  const Mesh bunny = read_mesh(test::bundled_mesh("bunny.ply"));
  EXPECT_THROW(image_error(bunny, bunny, {128, 2, "", 0}), UsageError);
  EXPECT_THROW(image_error(bunny, bunny, {128, 2, "", 9}), UsageError);
  EXPECT_THROW(image_error(bunny, bunny, {4096, 2, "", 4}), UsageError);  // 16384 samples per side
}

}  // namespace
}  // namespace visimp
