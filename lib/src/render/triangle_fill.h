// The triangle fill both CPU rasterizers share (raster.cpp: orthographic ID frames;
// perspective.cpp: perspective views): vertices snapped to a 1/256-pixel grid, exact
// 64-bit edge functions with the top-left fill rule, depth interpolated from the plane of
// the unsnapped vertices, ties kept by the triangle drawn first (GL_LESS).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "visimp/render/frame.h"

namespace visimp::raster {

constexpr int kSubpixelBits = 8;
constexpr std::int32_t kSubpixel = 1 << kSubpixelBits;
constexpr std::int32_t kHalfPixel = kSubpixel / 2;

struct FixedPoint {
  std::int64_t x, y;
};

// Screen coordinates are positive (the view contains the bounding sphere with a margin),
// so adding 0.5 and truncating rounds to the nearest grid point.
struct SnappedVertex {
  std::int32_t x, y;
};
inline SnappedVertex snap(const ScreenVertex& v) {
  return {static_cast<std::int32_t>(v.x * static_cast<float>(kSubpixel) + 0.5f),
          static_cast<std::int32_t>(v.y * static_cast<float>(kSubpixel) + 0.5f)};
}

// Smallest pixel index i whose centre 256 i + 128 is >= lo, and largest with centre <= hi
// (an arithmetic shift is a floor division, also for negative values).
inline int first_centre(std::int32_t lo) { return (lo - kHalfPixel + kSubpixel - 1) >> kSubpixelBits; }
inline int last_centre(std::int32_t hi) { return (hi - kHalfPixel) >> kSubpixelBits; }

// For a counter-clockwise triangle in a y-up image, an edge a→b is a "left" edge when it
// runs downward and a "top" edge when it is horizontal and runs leftward. Pixel centres
// exactly on other edges are left to the neighbouring triangle: bias 1 turns >= into >.
inline std::int64_t fill_rule_bias(const FixedPoint& a, const FixedPoint& b) {
  const bool left = b.y < a.y;
  const bool top = b.y == a.y && b.x < a.x;
  return (left || top) ? 0 : 1;
}

// Rows of a box spanning more than this many centres start near their first covered one
// (fill_triangle).
constexpr int kSkipWidth = 8;

// Where a row's covered run can start: an edge function w + k·step with w < 0 and step > 0
// turns non-negative at k = ceil(-w / step), estimated with the reciprocal of step and taken
// one pixel early (never late; a row no edge opens starts at 0, and one that never opens
// returns `last`).
struct RowStart {
  double inverse[3];
  std::int64_t step[3];
  RowStart(std::int64_t s0, std::int64_t s1, std::int64_t s2)
      : inverse{s0 > 0 ? 1.0 / double(s0) : 0.0, s1 > 0 ? 1.0 / double(s1) : 0.0, s2 > 0 ? 1.0 / double(s2) : 0.0},
        step{s0, s1, s2} {}
  int first_pixel(std::int64_t w0, std::int64_t w1, std::int64_t w2, int last) const {
    double k = 0;
    const std::int64_t w[3] = {w0, w1, w2};
    for (int i = 0; i < 3; ++i)
      if (w[i] < 0) {
        if (step[i] <= 0) return last + 1;  // this edge never opens along the row
        k = std::max(k, double(-w[i]) * inverse[i]);
      }
    k = std::floor(k) - 1;
    return k <= 0 ? 0 : (k >= double(last) ? last : static_cast<int>(k));
  }
};

/// Fills the pixel centres of one triangle with `id` where it is nearer than `depth`, in the
/// pixel box [x0, x1] × [y0, y1] (already clipped to the image). A clockwise triangle is
/// skipped when `cull_clockwise`, else drawn from its other side.
inline void fill_triangle(SnappedVertex p0, SnappedVertex p1, SnappedVertex p2, const ScreenVertex* s0,
                          const ScreenVertex* s1, const ScreenVertex* s2, int x0, int x1, int y0, int y1,
                          std::uint32_t id, bool cull_clockwise, int size, std::uint32_t* ids, float* depth) {
  FixedPoint a{p0.x, p0.y}, b{p1.x, p1.y}, c{p2.x, p2.y};
  std::int64_t area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (area2 == 0) return;
  if (area2 < 0) {
    if (cull_clockwise) return;
    std::swap(b, c);
    std::swap(s1, s2);
    area2 = -area2;
  }

  // Edge function of edge p→q at pixel centre (x, y): (q - p) × (centre - p), >= 0 inside.
  const FixedPoint origin{x0 * kSubpixel + kHalfPixel, y0 * kSubpixel + kHalfPixel};
  auto edge_at_origin = [&](const FixedPoint& p, const FixedPoint& q) {
    return (q.x - p.x) * (origin.y - p.y) - (q.y - p.y) * (origin.x - p.x) - fill_rule_bias(p, q);
  };
  std::int64_t row0 = edge_at_origin(b, c), row1 = edge_at_origin(c, a), row2 = edge_at_origin(a, b);
  const std::int64_t step_x0 = -(c.y - b.y) * kSubpixel, step_y0 = (c.x - b.x) * kSubpixel;
  const std::int64_t step_x1 = -(a.y - c.y) * kSubpixel, step_y1 = (a.x - c.x) * kSubpixel;
  const std::int64_t step_x2 = -(b.y - a.y) * kSubpixel, step_y2 = (b.x - a.x) * kSubpixel;
  // A box of one pixel centre that the triangle misses (the common case for the sub-pixel
  // triangles of a scan): done before the depth plane's division.
  if (x0 == x1 && y0 == y1 && (row0 | row1 | row2) < 0) return;

  // Depth plane through the three (unsnapped) vertices, evaluated at pixel centres.
  const double inv_area = 1.0 / static_cast<double>(area2);
  const double ex1 = static_cast<double>(b.x - a.x), ey1 = static_cast<double>(b.y - a.y);
  const double ex2 = static_cast<double>(c.x - a.x), ey2 = static_cast<double>(c.y - a.y);
  const double dz1 = static_cast<double>(s1->depth) - s0->depth, dz2 = static_cast<double>(s2->depth) - s0->depth;
  const double dzdx = (dz1 * ey2 - dz2 * ey1) * inv_area * kSubpixel;
  const double dzdy = (dz2 * ex1 - dz1 * ex2) * inv_area * kSubpixel;
  const double z_origin =
      s0->depth + (dzdx * static_cast<double>(origin.x - a.x) + dzdy * static_cast<double>(origin.y - a.y)) / kSubpixel;

  // A wide box's rows start at their first covered pixel, or one or two before it, and end at
  // the first uncovered one after it: a row's covered centres are one run (each edge function
  // is linear in x, so each keeps a half-line), and a long thin triangle's box is mostly empty
  // (testing every centre of the box, `visimp imgerr` of a CAD part took twice as long). The
  // start is estimated in double (|w| < 2^53, so off by under one pixel) and every pixel drawn
  // still passes the exact test: the pixels drawn are the same.
  auto plot = [&](int x, int y, std::size_t row) {
    const float z = static_cast<float>(z_origin + dzdx * (x - x0) + dzdy * (y - y0));
    const std::size_t p = row + static_cast<std::size_t>(x);
    if (z < depth[p]) {
      depth[p] = z;
      ids[p] = id;
    }
  };
  // Narrow boxes (a scan's or a refined mesh's small triangles) test every centre of a row;
  // compiled apart, so their loop carries none of the wide rows' work.
  auto fill_rows = [&](auto wide_box) {
    constexpr bool kWide = decltype(wide_box)::value;
    const RowStart start(kWide ? step_x0 : 0, kWide ? step_x1 : 0, kWide ? step_x2 : 0);
    for (int y = y0; y <= y1; ++y) {
      const int first = kWide ? x0 + start.first_pixel(row0, row1, row2, x1 - x0) : x0;
      const std::int64_t k = first - x0;
      std::int64_t w0 = row0 + k * step_x0, w1 = row1 + k * step_x1, w2 = row2 + k * step_x2;
      const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(size);
      bool entered = false;
      for (int x = first; x <= x1; ++x) {
        if ((w0 | w1 | w2) >= 0) {
          entered = true;
          plot(x, y, row);
        } else if (kWide && entered) {
          break;  // past the run
        }
        w0 += step_x0;
        w1 += step_x1;
        w2 += step_x2;
      }
      row0 += step_y0;
      row1 += step_y1;
      row2 += step_y2;
    }
  };
  if (x1 - x0 < kSkipWidth)
    fill_rows(std::false_type{});
  else
    fill_rows(std::true_type{});
}

}  // namespace visimp::raster
