#include "visimp/core/bounding_box.h"

#include <gtest/gtest.h>

#include <cmath>

namespace visimp {
namespace {

TEST(BoundingBox, SpansOnlyTheVerticesFacesUse) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1e9, -1e9, 5}, {2, 0, 0}, {0, 3, -1}, {std::nan(""), 0, 0}};
  m.faces = {{0, 2, 3}};  // vertices 1 (far away) and 4 (NaN) are unreferenced
  const BoundingBox box = bounding_box(m);
  EXPECT_EQ(box.min.x, 0);
  EXPECT_EQ(box.min.y, 0);
  EXPECT_EQ(box.min.z, -1);
  EXPECT_EQ(box.max.x, 2);
  EXPECT_EQ(box.max.y, 3);
  EXPECT_EQ(box.max.z, 0);
  EXPECT_DOUBLE_EQ(box.diagonal(), std::sqrt(4.0 + 9.0 + 1.0));
}

TEST(BoundingBox, WithoutFacesSpansEveryVertex) {
  Mesh points;
  points.positions = {{1, 2, 3}, {-1, 5, 0}};
  const BoundingBox box = bounding_box(points);
  EXPECT_EQ(box.min.x, -1);
  EXPECT_EQ(box.max.y, 5);
  EXPECT_EQ(box.min.z, 0);
  EXPECT_TRUE(bounding_box(Mesh{}).empty());
  EXPECT_EQ(bounding_box(Mesh{}).diagonal(), 0.0);
}

}  // namespace
}  // namespace visimp
