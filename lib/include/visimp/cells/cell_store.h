// Per-cell storage of the walkthrough LODs (docs/cells.md, "Cell files"): a directory holding
//   cells.json          the manifest: format, version, the scene's content hash, the grid and
//                       build options, the cells built and what building them took;
//   cell_Q_R.vcell      one binary file per cell (q, r its axial coordinates; "m" for minus),
// so a walk reads only the cells it passes through, each on its own.
//
// A .vcell (v1, little-endian): magic "VISCELL1", version, scene hash, q, r, then per entry
// its kind, object, s, source faces and either the kept face indices (full: ascending, delta
// varints) or the LOD mesh (float positions, varint faces) and its projective textures (view,
// crop, luminance bytes, 16-bit depths); last, an FNV-1a hash of all bytes before it. Readers refuse a file of another scene or cell, a wrong version, counts the
// bytes cannot hold, indices out of range, non-finite positions and any changed byte.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "visimp/cells/cell_lod.h"
#include "visimp/cells/hex_grid.h"
#include "visimp/cells/scene.h"

namespace visimp {

/// Of every object's mesh (positions and faces) and transform, in object order.
std::uint64_t hash_scene(const Scene& scene);

struct CellManifest {
  std::uint64_t scene_hash = 0;
  std::size_t objects = 0;
  double cell_size = 50, eye_height = 15, origin_x = 0, origin_y = 0;
  CellBuildOptions options;
  std::vector<HexCell> cells;           ///< the cells built, in build order
  std::vector<std::size_t> cell_faces;  ///< per cell: faces of its LOD set
  std::vector<double> cell_seconds;     ///< per cell: build time
  double seconds = 0;                   ///< whole build, wall
  HexGrid grid() const { return HexGrid(cell_size, eye_height, origin_x, origin_y); }
};

/// "cell_Q_R.vcell" (a minus sign written as 'm').
std::string cell_file_name(const HexCell& cell);

void write_cell(const CellLods& lods, std::uint64_t scene_hash, const std::string& path);
/// Throws IoError naming `path` and the problem (see the file comment).
CellLods read_cell(const std::string& path, const Scene& scene, std::uint64_t scene_hash, const HexCell& expected);
/// Parses bytes already read (the fuzzer's entry point).
CellLods parse_cell(const std::string& bytes, const std::string& path, const Scene& scene, std::uint64_t scene_hash,
                    const HexCell& expected);

void write_manifest(const CellManifest& manifest, const std::string& path);
/// Throws IoError for a missing or malformed manifest, another format or version.
CellManifest read_manifest(const std::string& path);

}  // namespace visimp
