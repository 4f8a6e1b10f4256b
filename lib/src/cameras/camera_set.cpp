// Camera sets (see camera_set.h). Subdivision keeps a child order that lets locate() walk
// down the hierarchy: corner children first, centre child last.
#include "visimp/cameras/camera_set.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "visimp/core/errors.h"

namespace visimp {
namespace {

Vec3 normalized(const Vec3& v) { return v / norm(v); }

// Inside test for the spherical triangle edge u→v of a counter-clockwise face: the great
// circle through u and v splits the sphere, the face lies on its left.
bool left_of(const Vec3& u, const Vec3& v, const Vec3& p) { return dot(p, cross(u, v)) >= 0.0; }

}  // namespace

SphereTessellation::SphereTessellation(int level) {
  if (level < 0 || level > kMaxLevel) {
    throw UsageError("octahedron level " + std::to_string(level) + " is outside 0.." + std::to_string(kMaxLevel));
  }
  vertices_ = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Root face r covers the octant with sign bits (x<0, y<0, z<0) = (r>>2, r>>1, r) & 1, so
  // locate() starts with three sign tests.
  std::vector<Face> roots(8);
  for (std::uint32_t r = 0; r < 8; ++r) {
    const VertexIndex x = (r & 4) ? 1 : 0, y = (r & 2) ? 3 : 2, z = (r & 1) ? 5 : 4;
    const int negatives = ((r >> 2) & 1) + ((r >> 1) & 1) + (r & 1);
    roots[r] = (negatives % 2 == 0) ? Face{x, y, z} : Face{x, z, y};
  }
  levels_.push_back(std::move(roots));

  for (int l = 0; l < level; ++l) {
    std::unordered_map<std::uint64_t, VertexIndex> midpoints;
    auto midpoint = [&](VertexIndex a, VertexIndex b) {
      const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      auto [it, inserted] = midpoints.emplace(key, static_cast<VertexIndex>(vertices_.size()));
      if (inserted) vertices_.push_back(normalized(vertices_[a] + vertices_[b]));
      return it->second;
    };
    std::vector<Face> children;
    children.reserve(levels_.back().size() * 4);
    for (const Face& f : levels_.back()) {
      const VertexIndex ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      children.push_back({f[0], ab, ca});
      children.push_back({ab, f[1], bc});
      children.push_back({ca, bc, f[2]});
      children.push_back({ab, bc, ca});
    }
    levels_.push_back(std::move(children));
  }
}

std::uint32_t SphereTessellation::locate(const Vec3& p) const {
  std::uint32_t face = (p.x < 0 ? 4u : 0u) | (p.y < 0 ? 2u : 0u) | (p.z < 0 ? 1u : 0u);
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    // The first three children of `face` are its corners; each is cut off by the great
    // circle through two midpoints (child 3, the centre, is what remains).
    const std::uint32_t first = 4 * face;
    const Face& corner0 = levels_[l][first];
    const Face& corner1 = levels_[l][first + 1];
    const Face& corner2 = levels_[l][first + 2];
    if (left_of(vertices_[corner0[1]], vertices_[corner0[2]], p)) {
      face = first;
    } else if (left_of(vertices_[corner1[2]], vertices_[corner1[0]], p)) {
      face = first + 1;
    } else if (left_of(vertices_[corner2[0]], vertices_[corner2[1]], p)) {
      face = first + 2;
    } else {
      face = first + 3;
    }
  }
  return face;
}

bool SphereTessellation::contains(std::uint32_t face, const Vec3& p) const {
  const Face& f = levels_.back()[face];
  const Vec3 &a = vertices_[f[0]], &b = vertices_[f[1]], &c = vertices_[f[2]];
  // A small negative slack accepts points on a shared border from either side.
  const double slack = -1e-12 * norm(p);
  return dot(p, a + b + c) > 0 && dot(p, cross(a, b)) >= slack && dot(p, cross(b, c)) >= slack &&
         dot(p, cross(c, a)) >= slack;
}

std::size_t octahedron_camera_count(int level) { return (std::size_t{4} << (2 * level)) + 2; }

CameraSet octahedron_cameras(int level) {
  SphereTessellation tessellation(level);
  return {"octahedron-k" + std::to_string(level), tessellation.vertices()};
}

CameraSet dodecahedron_cameras() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0, inv = 1.0 / phi;
  CameraSet set{"dodecahedron", {}};
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0}) set.directions.push_back(normalized({sx, sy, sz}));
  for (double s1 : {-1.0, 1.0}) {
    for (double s2 : {-1.0, 1.0}) {
      set.directions.push_back(normalized({0, s1 * inv, s2 * phi}));
      set.directions.push_back(normalized({s1 * inv, s2 * phi, 0}));
      set.directions.push_back(normalized({s1 * phi, 0, s2 * inv}));
    }
  }
  return set;
}

CameraSet read_camera_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path, std::string("cannot open camera list: ") + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(path, "read error");
  return parse_camera_list(text.str(), path);
}

CameraSet parse_camera_list(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  CameraSet set{path, {}};
  std::string line;
  for (std::size_t line_number = 1; std::getline(in, line); ++line_number) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    Vec3 d;
    if (!(fields >> d.x)) continue;  // blank or comment-only line
    std::string rest;
    if (!(fields >> d.y >> d.z) || (fields >> rest)) {
      throw IoError(path, "line " + std::to_string(line_number) + ": expected three numbers 'x y z'");
    }
    const double length = norm(d);
    if (!std::isfinite(length) || length == 0.0) {
      throw IoError(path, "line " + std::to_string(line_number) + ": camera direction must be finite and non-zero");
    }
    set.directions.push_back(d / length);
  }
  if (set.directions.empty()) throw IoError(path, "camera list has no directions");
  return set;
}

CameraSet camera_set_from_spec(const std::string& spec) {
  if (spec == "dodecahedron" || spec == "dodeca") return dodecahedron_cameras();
  if (spec.size() == 2 && spec[0] == 'k' && spec[1] >= '0' && spec[1] <= '9') {
    return octahedron_cameras(spec[1] - '0');
  }
  if (!spec.empty() && spec.find_first_not_of("0123456789") == std::string::npos) {
    for (int level = 0; level <= SphereTessellation::kMaxLevel; ++level) {
      if (spec == std::to_string(octahedron_camera_count(level))) return octahedron_cameras(level);
    }
    throw UsageError("camera set '" + spec + "': an octahedron set has 6, 18, 66, 258, 1026 or 4098 cameras");
  }
  return read_camera_file(spec);
}

}  // namespace visimp
