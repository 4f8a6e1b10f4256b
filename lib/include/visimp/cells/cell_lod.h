// The walkthrough-LOD paper's per-cell preprocessing (../shared/papers/002_*, §3.1, Figs. 1–2):
// for one hexagonal navigation cell, every object of the scene becomes one entry:
//   - inside the cell (its footprint meets the hexagon): the object as it is, less the faces
//     regional back-face culling proves unseen from the cell;
//   - outside, passing the self-occluding-error test (s ≤ Ts): an SVMesh — the faces
//     front-facing to the cell centre, collapsed with the paper's cost, weights from the depth
//     image at the centre, until every edge left is longer than Tl pixels as seen from there;
//   - outside, failing it: an MVMesh — the faces front-facing to the cell (centre or any
//     corner), weights the largest over the depth images at the centres of the cell and its
//     six neighbours, lengths the largest over the centre and corners.
// Pixels are those of the walk's output view (`output_resolution`², `fov_degrees`), which is
// what Ts and Tl are stated in.
//
// One deviation, for speed: an outside object is not collapsed from its full mesh each time
// but from the coarsest of a few quadric-simplified versions of it (built once per mesh)
// whose error, seen from the cell's nearest point, is below half a pixel — far objects start
// from a few thousand faces instead of hundreds of thousands, and the result differs from a
// collapse of the full mesh by less than the pixel the Tl rule already gives away.
#pragma once

#include <cstdint>
#include <vector>

#include "visimp/cells/hex_grid.h"
#include "visimp/cells/render_set.h"
#include "visimp/cells/scene.h"
#include "visimp/cells/textures.h"
#include "visimp/core/mesh.h"

namespace visimp {

struct CellBuildOptions {
  double ts_pixels = 5;    ///< Ts: the largest self-occlusion hole an SVMesh may show
  /// Tl: collapsing stops when every edge left is longer than this. 3 is the smallest of the
  /// paper's settings (its tables use 4.5): without textures 4.5 leaves a large LOD's
  /// shading faceted enough to miss 35 dB on our parks (docs/cells.md, sweeps).
  double tl_pixels = 3.0;
  int output_resolution = 1024;
  double fov_degrees = 60;
  int max_capture_resolution = 512;  ///< cap of the depth images and hole tests
  /// Quadric pre-simplified versions per mesh, each 1/4 of the previous (0: always the full mesh).
  int base_levels = 5;
  /// Projective textures of the original for every SVMesh (from the centre) and MVMesh (from
  /// the centre and corners), at the output's pixel size, at most this many pixels across.
  bool textures = true;
  int max_texture_resolution = 256;
  /// The paper's greedy object clustering (Fig. 5): objects passing the Ts test whose
  /// projections overlap share one SVMesh when the union still passes, and the surfaces the
  /// others hide from the centre are culled. At most `max_cluster` objects a cluster.
  bool clustering = false;
  int max_cluster = 8;
};
/// Throws UsageError naming the option when one is out of range.
void check_options(const CellBuildOptions& options);

/// in_cluster: drawn by another entry's cluster SVMesh (CellEntry::cluster names it).
enum class LodKind : std::uint8_t { full = 0, svmesh = 1, mvmesh = 2, in_cluster = 3 };
const char* to_string(LodKind kind);

struct CellEntry {
  LodKind kind = LodKind::full;
  std::uint32_t object = 0;            ///< index in Scene::objects
  std::vector<std::uint32_t> faces;    ///< full: the kept faces of the object's mesh, ascending
  Mesh mesh;                           ///< svmesh / mvmesh: in scene coordinates
  float self_occluding_error = 0;      ///< s in output pixels (outside objects)
  std::uint32_t source_faces = 0;      ///< faces of the version the LOD was collapsed from
  std::vector<ProjectiveTexture> textures;  ///< svmesh / mvmesh, with CellBuildOptions::textures
  /// A cluster's SVMesh: every member (this object first); in_cluster: the entry holding it.
  std::vector<std::uint32_t> cluster;
};

struct CellLods {
  HexCell cell;
  std::vector<CellEntry> entries;  ///< one per scene object, in object order
  std::size_t faces() const;       ///< faces drawn if nothing is frustum-culled
};

/// Holds the scene's per-mesh base versions; build() is const and may run on many threads.
class CellLodBuilder {
 public:
  CellLodBuilder(const Scene& scene, const HexGrid& grid, const CellBuildOptions& options);
  CellLods build(const HexCell& cell) const;
  /// The output's angular pixel size (radians) at the image centre.
  double pixel_angle() const { return pixel_angle_; }
  /// Whether object i's footprint (its x-y bounding circle) meets the cell's hexagon.
  bool inside(std::size_t object, const HexCell& cell) const;

 private:
  struct Version {
    Mesh mesh;             ///< in the mesh's own coordinates
    double error = 0;      ///< largest collapse error, in those coordinates
  };
  struct Placed {
    Vec3 centre;           ///< bounding-box centre, scene coordinates
    double radius = 0;     ///< bounding-sphere radius
    double footprint = 0;  ///< radius of the x-y bounding circle about the centre
    double scale = 1;      ///< the transform's largest stretch (error to scene units)
  };
  Mesh version_for(std::size_t object, double nearest_distance, std::uint32_t* source_faces) const;

  const Scene& scene_;
  HexGrid grid_;
  CellBuildOptions options_;
  double pixel_angle_;
  std::vector<std::vector<Version>> versions_;  ///< per scene mesh, finest first (the first is the mesh)
  std::vector<Placed> placed_;                   ///< per object
  std::vector<RenderSet> object_sets_;           ///< per object, whole, for the textures
};

/// The capture resolution that gives an object of angular radius `half_angle` (radians) about
/// the output's pixel size, clamped to [32, cap].
int capture_resolution(double half_angle, double pixel_angle, int cap);

}  // namespace visimp
