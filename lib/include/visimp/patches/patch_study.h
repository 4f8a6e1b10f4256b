// How well view reconstruction culls and how much it misses (Meruvia Pastor Figs. 4–5 and
// §4.2; Meruvia Pastor & Strothotte Fig. 7), from one sampling:
//
//   1. render per-face ID-bitfields once at the finest camera level asked for (coarser
//      octahedron levels are prefixes of its cameras);
//   2. per patch count, build the patches and derive their bitfields from the face bits
//      (a patch owns exactly the pixels its faces own);
//   3. culling rate per (unit, camera level): over random viewpoints on the sphere, the mean
//      fraction of faces not drawn;
//   4. at one camera level: render the full mesh and each reconstruction from random
//      viewpoints and count the pixels whose face differs (missed pixels), and, with a
//      timing renderer (OSMesa), the seconds per frame of full and culled drawing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/render/renderer.h"

namespace visimp {

struct PatchStudyOptions {
  std::vector<std::size_t> patch_counts = {50, 200, 1000, 2000};  ///< ID-bitfields (one unit per face) always come too
  int max_level = 4;              ///< octahedron levels 0..max_level: 6 .. 1026 cameras (5: 4098)
  int pixel_level = -1;           ///< level of the pixel and timing checks; -1 = max_level
  std::size_t viewpoints = 1000;  ///< random viewpoints for the culling rates
  std::size_t pixel_views = 20;   ///< random viewpoints rendered full and reconstructed
  std::size_t timing_frames = 4;  ///< frames timed per viewpoint and mesh with the timing renderer
  bool neighbour_fill = false;
  bool depth_test = true;
  std::uint64_t seed = 1;
};

/// Throws UsageError for out-of-range values.
void check_options(const PatchStudyOptions& options);

struct CullingPoint {
  std::string unit;         ///< "patches" or "faces"
  std::size_t patches = 0;  ///< units (the face count for "faces")
  std::size_t cameras = 0;
  double culling_rate = 0;  ///< mean over viewpoints of 1 − drawn faces / faces
  double min_culling = 0, max_culling = 0;
};

struct PixelCheck {
  std::string unit;
  std::size_t patches = 0, cameras = 0, views = 0;
  std::uint64_t differing_pixels = 0;  ///< face ID differs, summed over views
  /// Of those, pixels whose depth differs too (by > 1e-5 of the view depth): holes and
  /// faces behind them, not a coplanar face of another part winning a depth tie.
  std::uint64_t depth_differing_pixels = 0;
  std::uint64_t max_differing_pixels = 0;  ///< in the worst view
  std::size_t views_with_differences = 0;
  std::uint64_t mesh_pixels = 0;                                    ///< pixels showing the full mesh, summed over views
  double drawn_fraction = 0;                                        ///< mean over views
  double seconds_per_frame_full = 0, seconds_per_frame_culled = 0;  ///< 0 without a timing renderer
};

struct PatchStudy {
  std::size_t faces = 0;
  int resolution = 0;
  std::string sampler, timer;  ///< renderer names ("" = no timing)
  std::vector<std::size_t> patch_counts;
  std::vector<double> seconds_patches;  ///< per patch count
  double seconds_sampling = 0, seconds_total = 0;
  std::vector<CullingPoint> culling;
  std::vector<PixelCheck> pixels;
};

/// `sampler` renders the ID frames (sampling and pixel checks); `timer`, if given, is timed
/// drawing full and culled meshes (run it on one thread).
PatchStudy run_patch_study(const Mesh& mesh, Renderer& sampler, Renderer* timer, const PatchStudyOptions& options,
                           RenderObserver* observer = nullptr);

/// study.csv, study.json, culling_vs_samples.svg, culling_vs_patches.svg in `directory`.
void write_patch_study(const PatchStudy& study, const std::string& directory);
void write_patch_study_json(const PatchStudy& study, std::ostream& out);

/// `count` directions uniform on the unit sphere, the same on every machine for a seed.
std::vector<Vec3> random_directions(std::size_t count, std::uint64_t seed);

}  // namespace visimp
