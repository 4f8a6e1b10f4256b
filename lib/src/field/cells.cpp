// Cells of the visibility field (see cells.h).
#include "visimp/field/cells.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "visimp/core/errors.h"
#include "visimp/core/union_find.h"

namespace visimp {

std::string cell_mode_name(CellMode mode) {
  switch (mode) {
    case CellMode::Polygon:
      return "polygon";
    case CellMode::SceneGrid:
      return "scene";
    default:
      return "object";
  }
}

CellMode parse_cell_mode(const std::string& name) {
  if (name == "object") return CellMode::ObjectGrid;
  if (name == "polygon") return CellMode::Polygon;
  if (name == "scene") return CellMode::SceneGrid;
  throw UsageError("cell mode must be object, polygon or scene, got '" + name + "'");
}

void check_options(const CellOptions& options, std::size_t faces) {
  if (options.grid < 1 || options.grid > kMaxGrid) {
    throw OptionError(&options.grid, "CellOptions::grid", "must be in [1, " + std::to_string(kMaxGrid) + "]");
  }
  if (!options.face_objects.empty() && options.face_objects.size() != faces) {
    throw OptionError(&options.face_objects, "CellOptions::face_objects",
                      "must hold one object per face (" + std::to_string(faces) + "), got " +
                          std::to_string(options.face_objects.size()));
  }
}

std::vector<std::uint32_t> face_components(const Mesh& mesh, std::size_t* count) {
  UnionFind sets(mesh.num_vertices());
  for (const Face& f : mesh.faces) {
    sets.unite(f[0], f[1]);
    sets.unite(f[0], f[2]);
  }
  std::unordered_map<std::uint32_t, std::uint32_t> index;
  std::vector<std::uint32_t> out(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const auto [it, added] = index.emplace(sets.find(mesh.faces[f][0]), static_cast<std::uint32_t>(index.size()));
    out[f] = it->second;
  }
  if (count) *count = index.size();
  return out;
}

void CellPartition::index_cell_faces() {
  const std::size_t cells = keys.size();
  cell_offsets.assign(cells + 1, 0);
  for (std::uint32_t c : face_cell) ++cell_offsets[c + 1];
  for (std::size_t c = 0; c < cells; ++c) cell_offsets[c + 1] += cell_offsets[c];
  cell_faces.resize(face_cell.size());
  std::vector<std::uint32_t> next(cell_offsets.begin(), cell_offsets.end() - 1);
  for (std::size_t f = 0; f < face_cell.size(); ++f) cell_faces[next[face_cell[f]]++] = static_cast<std::uint32_t>(f);
}

void CellPartition::index_faces(const Mesh& mesh) {
  index_cell_faces();
  bounds.assign(keys.size(), BoundingBox{});
  for (std::size_t f = 0; f < face_cell.size(); ++f) {
    for (VertexIndex v : mesh.faces[f]) bounds[face_cell[f]].extend(mesh.positions[v]);
  }
}

namespace {

// The grid of one object: cubic cells, `grid` of them along the longest side of its box.
struct Grid {
  Vec3 origin;
  double cell = 1;
  std::array<int, 3> dims{1, 1, 1};

  Grid(const BoundingBox& box, int grid) {
    origin = box.min;
    const Vec3 extent = box.max - box.min;
    const double longest = std::max({extent.x, extent.y, extent.z});
    cell = longest > 0 ? longest / grid : 1;
    const double e[3] = {extent.x, extent.y, extent.z};
    for (int a = 0; a < 3; ++a) dims[a] = std::clamp(static_cast<int>(std::ceil(e[a] / cell)), 1, grid);
  }
  std::array<int, 3> cell_of(const Vec3& p) const {
    const double q[3] = {(p.x - origin.x) / cell, (p.y - origin.y) / cell, (p.z - origin.z) / cell};
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = std::isfinite(q[a]) ? std::clamp(static_cast<int>(q[a]), 0, dims[a] - 1) : 0;
    return c;
  }
};

}  // namespace

CellPartition partition_cells(const Mesh& mesh, const CellOptions& options) {
  check_options(options, mesh.num_faces());
  CellPartition out;
  const std::size_t faces = mesh.num_faces();
  std::vector<std::uint32_t> object;
  if (options.mode == CellMode::SceneGrid) {
    object.assign(faces, 0);
    out.objects = faces ? 1 : 0;
  } else if (!options.face_objects.empty()) {
    // Group numbers may be sparse: objects are numbered densely in order of first appearance.
    std::unordered_map<std::uint32_t, std::uint32_t> dense;
    object.resize(faces);
    for (std::size_t f = 0; f < faces; ++f) {
      object[f] = dense.emplace(options.face_objects[f], static_cast<std::uint32_t>(dense.size())).first->second;
    }
    out.objects = dense.size();
  } else {
    object = face_components(mesh, &out.objects);
  }

  // Sort faces by (object, cell) so ids come in (object, cz, cy, cx) order.
  std::vector<std::uint64_t> code(faces);
  if (options.mode == CellMode::Polygon) {
    for (std::size_t f = 0; f < faces; ++f) code[f] = f;
  } else {
    std::vector<BoundingBox> boxes(out.objects);
    for (std::size_t f = 0; f < faces; ++f) {
      for (VertexIndex v : mesh.faces[f]) boxes[object[f]].extend(mesh.positions[v]);
    }
    std::vector<Grid> grids;
    grids.reserve(out.objects);
    for (const BoundingBox& b : boxes) grids.emplace_back(b, options.grid);
    for (std::size_t f = 0; f < faces; ++f) {
      const Face& t = mesh.faces[f];
      const Vec3 centroid = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
      const auto c = grids[object[f]].cell_of(centroid);
      code[f] = (std::uint64_t{object[f]} << 24) | (std::uint64_t(c[2]) << 16) | (std::uint64_t(c[1]) << 8) |
                std::uint64_t(c[0]);
    }
  }
  std::vector<std::uint64_t> distinct(code);
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  out.keys.resize(distinct.size());
  for (std::size_t c = 0; c < distinct.size(); ++c) {
    const std::uint64_t k = distinct[c];
    if (options.mode == CellMode::Polygon) {
      out.keys[c].object = object[k];
    } else {
      out.keys[c] = {static_cast<std::uint32_t>(k >> 24), static_cast<std::uint8_t>(k & 0xff),
                     static_cast<std::uint8_t>((k >> 8) & 0xff), static_cast<std::uint8_t>((k >> 16) & 0xff)};
    }
  }
  out.face_cell.resize(faces);
  for (std::size_t f = 0; f < faces; ++f) {
    out.face_cell[f] =
        static_cast<std::uint32_t>(std::lower_bound(distinct.begin(), distinct.end(), code[f]) - distinct.begin());
  }
  out.index_faces(mesh);
  return out;
}

}  // namespace visimp
