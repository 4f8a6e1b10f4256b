// The geometry elements a visibility field refers to (Blais & Poulin §3.2): each object of
// the scene is divided into its own regular grid of cells and a sample stores cell ids.
//
// An id is a compact integer: the index of a non-empty cell, 0-based, in (object, cz, cy,
// cx) order. The paper's 4-byte record (mesh index and three cell coordinates, Fig. 5)
// stays available as the cell's key. The paper's alternatives are options: one id per
// polygon (§3.2, choice 1) and one grid over the whole scene (§3.2, §7).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "visimp/core/bounding_box.h"
#include "visimp/core/mesh.h"

namespace visimp {

enum class CellMode : std::uint8_t {
  ObjectGrid = 0,  ///< a grid per object (the paper's choice)
  Polygon = 1,     ///< every face its own cell
  SceneGrid = 2,   ///< one grid over the scene's box
};

/// "object", "polygon", "scene"; parse_cell_mode throws UsageError for anything else.
std::string cell_mode_name(CellMode mode);
CellMode parse_cell_mode(const std::string& name);

struct CellOptions {
  CellMode mode = CellMode::ObjectGrid;
  /// Cells along the longest side of each grid (object or scene); cubic cells, so a flat
  /// object gets few cells across its thin side. 1..255 (a coordinate fits a byte, Fig. 5).
  int grid = 16;
  /// Empty: objects are the connected components (faces sharing a vertex). Otherwise one
  /// object id per face, given by the user (a group).
  std::vector<std::uint32_t> face_objects;
};

inline constexpr int kMaxGrid = 255;

/// Throws OptionError for an out-of-range grid or a face_objects of the wrong size.
void check_options(const CellOptions& options, std::size_t faces);

/// Fig. 5's record: which object and which cell of its grid.
struct CellKey {
  std::uint32_t object = 0;
  std::uint8_t cx = 0, cy = 0, cz = 0;
};

struct CellPartition {
  std::size_t objects = 0;
  std::vector<std::uint32_t> face_cell;  ///< per face, its cell id
  std::vector<CellKey> keys;             ///< per cell
  std::vector<BoundingBox> bounds;       ///< per cell, of its faces' vertices
  /// Faces of cell c, ascending: cell_faces[cell_offsets[c] .. cell_offsets[c + 1]).
  std::vector<std::uint32_t> cell_offsets, cell_faces;

  std::size_t num_cells() const { return keys.size(); }
  /// Rebuilds cell_offsets and cell_faces from face_cell (what a reader derives).
  void index_cell_faces();
  /// The same, and the cells' bounding boxes from the mesh.
  void index_faces(const Mesh& mesh);
};

/// A face belongs to the cell holding its centroid. Cells without faces get no id.
CellPartition partition_cells(const Mesh& mesh, const CellOptions& options);

/// Connected components over shared vertices: per face, a component index 0..n−1 in order
/// of first appearance.
std::vector<std::uint32_t> face_components(const Mesh& mesh, std::size_t* count = nullptr);

}  // namespace visimp
