#include "visimp/core/validate.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_meshes.h"
#include "visimp/core/errors.h"

namespace visimp {
namespace {

TEST(Validate, AcceptsAGrid) { EXPECT_TRUE(validate(test::grid(2)).ok()); }

TEST(Validate, FindsOutOfRangeIndexAndNonFiniteCoordinate) {
  Mesh m = test::grid(1);
  m.faces.push_back({0, 1, 99});
  m.positions[2].y = std::nan("");
  const ValidationReport r = validate(m);
  EXPECT_EQ(r.out_of_range_indices, 1u);
  EXPECT_EQ(r.non_finite_coordinates, 1u);
  EXPECT_FALSE(r.ok());
  EXPECT_THROW(require_valid(m, "m"), InvalidMeshError);
}

TEST(Validate, FindsQualityOfTheWrongSize) {
  Mesh m = test::grid(1);
  m.face_quality = {1.0f};  // 2 faces
  EXPECT_EQ(validate(m).quality_size_mismatches, 1u);
}

}  // namespace
}  // namespace visimp
