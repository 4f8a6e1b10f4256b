// The walkthrough-LOD paper's run time (../shared/papers/002_*, §3.2 and §4): along a camera
// path, each frame is drawn from the LOD set of the cell holding the eye (inside objects whole,
// outside ones as SVMesh/MVMesh, frustum-culled per mesh), and — for the study — the full
// scene two ways: everything (the paper's configuration A) and frustum-culled per object (B).
// Frames are compared in PSNR on luminance Y = 0.299R + 0.587G + 0.114B (§4); our shading is
// grey, so Y is the shaded grey level itself.
//
// Cells are read from the cell directory on demand through a CellCache; with prefetching on, a
// lower-priority thread reads the six neighbours of the current cell ahead of the crossing
// (§3.2). The prefetcher changes when a cell is read, never what is drawn.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "visimp/cells/cell_store.h"
#include "visimp/cells/hex_grid.h"
#include "visimp/cells/render_set.h"
#include "visimp/cells/scene.h"
#include "visimp/render/perspective.h"

namespace visimp {

struct CameraPose {
  Vec3 position;
  Vec3 direction;  ///< need not be unit
};

/// A path file: one pose a line, "x y z dx dy dz"; blank lines and '#' comments skipped.
/// Throws IoError naming the file and line for anything else.
std::vector<CameraPose> read_camera_path(const std::string& path);
/// A closed loop through the scene at eye height: an ellipse over the middle 70% of the
/// objects' x-y extent, looking along it and swinging ±30° to the sides, `frames` poses. It
/// walks around objects: a pose inside an object's ground footprint (the x-y disc holding its
/// vertices, widened by 10%) is pushed radially out of it.
std::vector<CameraPose> auto_camera_path(const Scene& scene, double eye_height, std::size_t frames);

/// A cell's LOD set (inside objects' kept faces, LOD meshes with their textures), one group per entry.
RenderSet cell_set(const Scene& scene, CellLods lods);

PerspectiveView frame_view(const CameraPose& pose, double fov_degrees, int resolution, double near);

/// Cells read from a cell directory, kept while in use, optionally prefetched.
class CellCache {
 public:
  CellCache(const Scene& scene, std::string directory, const CellManifest& manifest, bool prefetch);
  ~CellCache();
  CellCache(const CellCache&) = delete;
  CellCache& operator=(const CellCache&) = delete;
  /// The cell's set, reading it now unless it is cached (or being read: then waiting).
  /// `read_seconds` is what this call spent reading or waiting. Throws IoError when the cell
  /// was not built, or its file is refused.
  std::shared_ptr<const RenderSet> get(const HexCell& cell, double* read_seconds);
  /// Queues the built neighbours of `cell` for the prefetch thread (no-op without prefetching).
  void prefetch_around(const HexCell& cell);
  bool built(const HexCell& cell) const;
  std::size_t reads() const { return reads_; }

 private:
  struct Slot {
    std::shared_ptr<const RenderSet> set;
    bool loading = false;
    std::uint64_t used = 0;
    std::string error;
  };
  std::shared_ptr<const RenderSet> load(const HexCell& cell) const;
  void prefetch_loop();
  void evict_locked();
  static std::uint64_t key(const HexCell& c);

  const Scene& scene_;
  std::string directory_;
  std::uint64_t scene_hash_;
  HexGrid grid_;
  std::map<std::uint64_t, HexCell> built_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::map<std::uint64_t, Slot> slots_;
  std::vector<HexCell> queue_;
  std::uint64_t clock_ = 0;
  std::size_t reads_ = 0;
  bool stop_ = false;
  std::thread prefetcher_;
};

struct WalkOptions {
  int resolution = 1024;
  double fov_degrees = 60;
  Shading shading = Shading::smooth;
  bool textures = true;  ///< LOD meshes take their grey from their projective textures
  bool prefetch = true;
  /// Every k-th frame is also drawn full (A) and frustum-culled (B) for PSNR and timing; 0: never.
  std::size_t reference_every = 1;
};

struct WalkFrame {
  std::size_t index = 0;
  CameraPose pose;
  HexCell cell;
  bool crossing = false;  ///< first frame in a new cell
  std::size_t faces_a = 0, faces_b = 0, faces_c = 0;
  double ms_a = 0, ms_b = 0, ms_c = 0;  ///< draw + shade; C also includes reading its cell
  double read_ms = 0;                   ///< of ms_c: reading or waiting for the cell
  double psnr = 0;                      ///< C against A (NaN without a reference frame)
  std::uint64_t image_hash = 0;         ///< of C's image
};

/// Walks the path; `on_frame` (may be empty) sees each frame and its images (A's empty when
/// not drawn). Throws IoError for a path leaving the built cells.
std::vector<WalkFrame> walk(const Scene& scene, const std::string& directory, const CellManifest& manifest,
                            const std::vector<CameraPose>& path, const WalkOptions& options,
                            const std::function<void(const WalkFrame&, const FrameImage& c, const FrameImage& a)>&
                                on_frame = {});

}  // namespace visimp
