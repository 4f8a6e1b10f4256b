// Hexagonal cells (see hex_grid.h).
//
// Point location: the point is mapped to fractional axial coordinates and rounded in cube
// coordinates (the standard hex rounding); that cell and its six neighbours are then
// compared by distance to their centres (see cell_of).
#include "visimp/cells/hex_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "visimp/core/errors.h"

namespace visimp {
namespace {

constexpr double kSqrt3 = 1.7320508075688772;

}  // namespace

HexGrid::HexGrid(double size, double eye_height, double origin_x, double origin_y)
    : size_(size), eye_height_(eye_height), origin_x_(origin_x), origin_y_(origin_y) {
  if (!(size > 0) || !std::isfinite(size)) throw OptionError(&size_, "HexGrid::size", "must be positive and finite");
  if (!std::isfinite(eye_height)) throw OptionError(&eye_height_, "HexGrid::eye_height", "must be finite");
  if (!std::isfinite(origin_x) || !std::isfinite(origin_y))
    throw OptionError(nullptr, "HexGrid::origin", "must be finite");
}

std::array<double, 2> HexGrid::center(const HexCell& c) const {
  return {origin_x_ + size_ * kSqrt3 * (c.q + 0.5 * c.r), origin_y_ + size_ * 1.5 * c.r};
}

Vec3 HexGrid::eye_at_center(const HexCell& c) const {
  const auto p = center(c);
  return {p[0], p[1], eye_height_};
}

std::array<Vec3, 6> HexGrid::corners(const HexCell& c) const {
  const auto p = center(c);
  std::array<Vec3, 6> out;
  for (int k = 0; k < 6; ++k) {
    const double angle = M_PI / 2 + k * M_PI / 3;  // pointy top: the first corner straight up
    out[static_cast<std::size_t>(k)] = {p[0] + size_ * std::cos(angle), p[1] + size_ * std::sin(angle), eye_height_};
  }
  return out;
}

std::array<HexCell, 6> HexGrid::neighbours(const HexCell& c) const {
  return {HexCell{c.q + 1, c.r}, HexCell{c.q, c.r + 1}, HexCell{c.q - 1, c.r + 1},
          HexCell{c.q - 1, c.r}, HexCell{c.q, c.r - 1}, HexCell{c.q + 1, c.r - 1}};
}

bool HexGrid::contains(const HexCell& c, double x, double y) const {
  // A pointy-topped hexagon is the intersection of three slabs: |dx| ≤ √3/2·s and
  // |±dx/2 + √3/2·dy| ≤ √3/2·s (the edge normals at 0°, 60° and 120°; apothem √3/2·s).
  const auto p = center(c);
  const double dx = x - p[0], dy = y - p[1];
  const double half_width = 0.5 * kSqrt3 * size_;
  return std::abs(dx) <= half_width && std::abs(0.5 * dx + 0.5 * kSqrt3 * dy) <= half_width &&
         std::abs(-0.5 * dx + 0.5 * kSqrt3 * dy) <= half_width;
}

HexCell HexGrid::cell_of(double x, double y) const {
  const double px = (x - origin_x_) / size_, py = (y - origin_y_) / size_;
  const double fq = kSqrt3 / 3 * px - py / 3, fr = 2.0 / 3 * py;
  // Cube rounding: x + y + z = 0, fix the coordinate with the largest rounding error.
  const double fs = -fq - fr;
  double rq = std::round(fq), rr = std::round(fr);
  const double rs = std::round(fs);
  const double dq = std::abs(rq - fq), dr = std::abs(rr - fr), ds = std::abs(rs - fs);
  if (dq > dr && dq > ds) {
    rq = -rr - rs;
  } else if (dr > ds) {
    rr = -rq - rs;
  }
  const HexCell guess{static_cast<int>(rq), static_cast<int>(rr)};
  // The tiling is the Voronoi diagram of the centres: the nearest centre owns the point. The
  // rounded guess is that cell or next to it, so the nearest of these seven decides, and
  // exactly one wins (a tie goes to the smaller (r, q)) — a partition even in floating point,
  // where separately computed hexagon edges would leave slivers or overlaps.
  HexCell best = guess;
  double best_d = std::numeric_limits<double>::infinity();
  auto consider = [&](const HexCell& c) {
    const auto p = center(c);
    const double d = (x - p[0]) * (x - p[0]) + (y - p[1]) * (y - p[1]);
    if (d < best_d || (d == best_d && (c.r < best.r || (c.r == best.r && c.q < best.q)))) {
      best = c;
      best_d = d;
    }
  };
  consider(guess);
  for (const HexCell& n : neighbours(guess)) consider(n);
  return best;
}

std::vector<HexCell> HexGrid::cells_covering(double x0, double y0, double x1, double y1) const {
  std::vector<HexCell> out;
  if (!(x0 <= x1 && y0 <= y1)) return out;
  const HexCell a = cell_of(x0, y0), b = cell_of(x1, y1);
  const int r0 = std::min(a.r, b.r) - 1, r1 = std::max(a.r, b.r) + 1;
  for (int r = r0; r <= r1; ++r) {
    const HexCell left = cell_of(x0, origin_y_ + size_ * 1.5 * r), right = cell_of(x1, origin_y_ + size_ * 1.5 * r);
    for (int q = std::min(left.q, right.q) - 2; q <= std::max(left.q, right.q) + 2; ++q) {
      const HexCell c{q, r};
      const auto p = center(c);
      // The hexagon's box is [±√3/2·s] × [±s] around its centre.
      if (p[0] + 0.5 * kSqrt3 * size_ >= x0 && p[0] - 0.5 * kSqrt3 * size_ <= x1 && p[1] + size_ >= y0 &&
          p[1] - size_ <= y1)
        out.push_back(c);
    }
  }
  return out;
}

}  // namespace visimp
