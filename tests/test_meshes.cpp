#include "test_meshes.h"

#include <cmath>
#include <filesystem>

#include <algorithm>
#include <array>
#include <map>

namespace visimp::test {

Mesh grid(int n) {
  Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.positions.push_back({double(i), double(j), 0.0});
  auto id = [n](int i, int j) { return VertexIndex(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

Mesh subdivided_cube(int n) {
  Mesh m;
  std::map<std::array<int, 3>, VertexIndex> index;
  auto vertex = [&](int x, int y, int z) {
    const std::array<int, 3> key{x, y, z};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const VertexIndex v = VertexIndex(m.positions.size());
    m.positions.push_back({double(x) / n, double(y) / n, double(z) / n});
    index.emplace(key, v);
    return v;
  };
  // For each axis and side, a grid spanned by the other two axes, wound so normals point out.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side <= 1; ++side) {
      const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
          auto at = [&](int du, int dv) {
            int c[3];
            c[axis] = side * n;
            c[u_axis] = a + du;
            c[v_axis] = b + dv;
            return vertex(c[0], c[1], c[2]);
          };
          const VertexIndex p00 = at(0, 0), p10 = at(1, 0), p11 = at(1, 1), p01 = at(0, 1);
          // u × v = +axis, so (p00, p10, p11) faces +axis; flip it on the low side.
          if (side == 1) {
            m.faces.push_back({p00, p10, p11});
            m.faces.push_back({p00, p11, p01});
          } else {
            m.faces.push_back({p00, p11, p10});
            m.faces.push_back({p00, p01, p11});
          }
        }
    }
  return m;
}

Mesh icosphere(int levels, double radius) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  Mesh m;
  m.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                 {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  m.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
             {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
             {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<VertexIndex, VertexIndex>, VertexIndex> mid;
    auto midpoint = [&](VertexIndex a, VertexIndex b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const VertexIndex v = VertexIndex(m.positions.size());
      m.positions.push_back((m.positions[a] + m.positions[b]) * 0.5);
      mid.emplace(key, v);
      return v;
    };
    std::vector<Face> faces;
    for (const Face& f : m.faces) {
      const VertexIndex a = midpoint(f[0], f[1]), b = midpoint(f[1], f[2]), c = midpoint(f[2], f[0]);
      faces.push_back({f[0], a, c});
      faces.push_back({f[1], b, a});
      faces.push_back({f[2], c, b});
      faces.push_back({a, b, c});
    }
    m.faces = faces;
  }
  for (Vec3& p : m.positions) p = p * (radius / norm(p));
  return m;
}

std::vector<std::string> real_mesh_paths(bool include_shared) {
  std::vector<std::string> paths;
  for (const char* f : {"bunny.ply", "fandisk_cad.ply", "teapot.ply", "kicad_esp_wroom02.ply", "aneurysm_open.ply"})
    paths.push_back(bundled_mesh(f));
  if (include_shared)
    for (const char* f : {"ifc_house_messy.ply", "kicad_cap_snapin_d40.ply", "kicad_dsub62_male.ply"})
      paths.push_back(shared_mesh(f));
  return paths;
}

std::string bundled_mesh(const std::string& file) { return std::string(VISIMP_MESHES_DIR) + "/" + file; }
std::string shared_mesh(const std::string& file) { return std::string(VISIMP_SHARED_MESHES_DIR) + "/" + file; }

}  // namespace visimp::test
