// The walk: paths, render sets, shading, PSNR and the prefetching cell cache (see walk.h).
#include "visimp/cells/walk.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"
#include "visimp/core/stopwatch.h"

namespace visimp {
namespace {
constexpr double kDegree = M_PI / 180;
}  // namespace

std::vector<CameraPose> read_camera_path(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open the camera path");
  std::vector<CameraPose> out;
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    double v[6];
    int n = 0;
    while (n < 6 && fields >> v[n]) ++n;
    std::string rest;
    if (n == 0 && !(fields.clear(), fields >> rest)) continue;  // blank
    if (n != 6 || (fields >> rest))
      throw IoError(path, "line " + std::to_string(number) + ": expected 'x y z dx dy dz'");
    for (double x : v)
      if (!std::isfinite(x)) throw IoError(path, "line " + std::to_string(number) + ": a number is not finite");
    const Vec3 d{v[3], v[4], v[5]};
    if (!(norm(d) > 0)) throw IoError(path, "line " + std::to_string(number) + ": the direction is zero");
    out.push_back({{v[0], v[1], v[2]}, d});
  }
  if (out.empty()) throw IoError(path, "the camera path has no poses");
  return out;
}

std::vector<CameraPose> auto_camera_path(const Scene& scene, double eye_height, std::size_t frames) {
  // Each object's ground footprint: the x-y disc around its box centre holding its vertices.
  struct Footprint {
    double x = 0, y = 0, radius = 0;
  };
  BoundingBox box;
  std::vector<Footprint> footprints;
  std::vector<Vec3> placed;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    placed.clear();
    BoundingBox object_box;
    for (const Vec3& p : scene.meshes[o.mesh].positions) {
      placed.push_back(transform_point(o.transform, p));
      object_box.extend(placed.back());
    }
    if (placed.empty()) continue;
    box.extend(object_box.min);
    box.extend(object_box.max);
    Footprint f{0.5 * (object_box.min.x + object_box.max.x), 0.5 * (object_box.min.y + object_box.max.y), 0};
    for (const Vec3& p : placed) f.radius = std::max(f.radius, std::hypot(p.x - f.x, p.y - f.y));
    footprints.push_back(f);
  }
  const double cx = 0.5 * (box.min.x + box.max.x), cy = 0.5 * (box.min.y + box.max.y);
  const double ax = 0.35 * (box.max.x - box.min.x), ay = 0.35 * (box.max.y - box.min.y);
  // A visitor walks around objects, not through them: a pose inside a footprint (plus a
  // margin) is pushed radially out of it. Without this the ellipse passes through statues and
  // the frames from inside a solid, where the full scene shows back faces that any culling
  // rightly drops, dominate the worst PSNR. A few passes settle overlapping footprints.
  auto walk_around = [&](Vec3 p) {
    for (int pass = 0; pass < 8; ++pass) {
      bool moved = false;
      for (const Footprint& f : footprints) {
        const double clear = 1.1 * f.radius, dx = p.x - f.x, dy = p.y - f.y, d = std::hypot(dx, dy);
        if (!(d < clear)) continue;
        const double ux = d > 0 ? dx / d : 1, uy = d > 0 ? dy / d : 0;  // the centre itself: leave along +x
        p.x = f.x + ux * clear;
        p.y = f.y + uy * clear;
        moved = true;
      }
      if (!moved) break;
    }
    return p;
  };
  std::vector<CameraPose> out;
  for (std::size_t k = 0; k < frames; ++k) {
    const double t = 2 * M_PI * static_cast<double>(k) / static_cast<double>(frames);
    const Vec3 p = walk_around({cx + ax * std::cos(t), cy + ay * std::sin(t), eye_height});
    const double heading = std::atan2(ay * std::cos(t), -ax * std::sin(t)) + 30 * kDegree * std::sin(5 * t);
    out.push_back({p, {std::cos(heading), std::sin(heading), 0}});
  }
  return out;
}

RenderSet cell_set(const Scene& scene, CellLods lods) {
  RenderSet set;
  for (CellEntry& e : lods.entries) {
    if (e.kind == LodKind::in_cluster) continue;  // drawn by its cluster's SVMesh
    if (e.kind == LodKind::full) {
      set.add(scene.object_mesh(e.object), &e.faces, e.object);
    } else {
      set.add(e.mesh, nullptr, e.object);
      set.groups.back().textures = std::move(e.textures);
    }
  }
  set.finish();
  return set;
}

PerspectiveView frame_view(const CameraPose& pose, double fov_degrees, int resolution, double near) {
  return PerspectiveView::looking_at(pose.position, pose.position + pose.direction, fov_degrees, resolution, near);
}


// ---- CellCache --------------------------------------------------------------------------

std::uint64_t CellCache::key(const HexCell& c) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(c.q)) << 32) | static_cast<std::uint32_t>(c.r);
}

CellCache::CellCache(const Scene& scene, std::string directory, const CellManifest& manifest, bool prefetch)
    : scene_(scene), directory_(std::move(directory)), scene_hash_(manifest.scene_hash), grid_(manifest.grid()) {
  for (const HexCell& c : manifest.cells) built_[key(c)] = c;
  if (prefetch) prefetcher_ = std::thread([this] { prefetch_loop(); });
}

CellCache::~CellCache() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  if (prefetcher_.joinable()) prefetcher_.join();
}

bool CellCache::built(const HexCell& cell) const { return built_.count(key(cell)) != 0; }

std::shared_ptr<const RenderSet> CellCache::load(const HexCell& cell) const {
  const CellLods lods = read_cell(directory_ + "/" + cell_file_name(cell), scene_, scene_hash_, cell);
  return std::make_shared<const RenderSet>(cell_set(scene_, lods));
}

void CellCache::evict_locked() {
  // Keep the 14 most recently used cells: the current one, its neighbours and a margin.
  constexpr std::size_t kKeep = 14;
  while (slots_.size() > kKeep) {
    auto oldest = slots_.end();
    for (auto it = slots_.begin(); it != slots_.end(); ++it) {
      if (it->second.loading) continue;
      if (oldest == slots_.end() || it->second.used < oldest->second.used) oldest = it;
    }
    if (oldest == slots_.end()) return;
    slots_.erase(oldest);
  }
}

std::shared_ptr<const RenderSet> CellCache::get(const HexCell& cell, double* read_seconds) {
  const auto start = std::chrono::steady_clock::now();
  if (!built(cell))
    throw IoError(directory_, "cell (" + std::to_string(cell.q) + ", " + std::to_string(cell.r) +
                                  ") was not built (the path leaves the cells in cells.json)");
  const std::uint64_t k = key(cell);
  std::unique_lock<std::mutex> lock(mutex_);
  Slot& slot = slots_[k];
  slot.used = ++clock_;
  changed_.wait(lock, [&] { return !slot.loading; });
  if (!slot.set) {
    if (!slot.error.empty()) throw IoError(directory_, slot.error);
    slot.loading = true;
    lock.unlock();
    std::shared_ptr<const RenderSet> set;
    try {
      set = load(cell);
    } catch (...) {
      lock.lock();
      slots_[k].loading = false;
      changed_.notify_all();
      throw;
    }
    lock.lock();
    Slot& s = slots_[k];
    s.set = std::move(set);
    s.loading = false;
    ++reads_;
    changed_.notify_all();
  }
  std::shared_ptr<const RenderSet> out = slots_[k].set;
  evict_locked();
  if (read_seconds) *read_seconds = seconds_since(start);
  return out;
}

void CellCache::prefetch_around(const HexCell& cell) {
  if (!prefetcher_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.clear();
    for (const HexCell& n : grid_.neighbours(cell)) {
      if (built(n)) queue_.push_back(n);
    }
  }
  changed_.notify_all();
}

void CellCache::prefetch_loop() {
  // Below the drawing thread: reading ahead must not slow the frames it serves (Linux lets
  // one thread's nice value differ from its process's).
  setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    changed_.wait(lock, [&] { return stop_ || !queue_.empty(); });
    if (stop_) return;
    const HexCell cell = queue_.front();
    queue_.erase(queue_.begin());
    const std::uint64_t k = key(cell);
    Slot& slot = slots_[k];
    if (slot.set || slot.loading || !slot.error.empty()) continue;
    slot.loading = true;
    slot.used = ++clock_;
    lock.unlock();
    std::shared_ptr<const RenderSet> set;
    std::string error;
    try {
      set = load(cell);
    } catch (const std::exception& e) {
      error = e.what();  // reported when the walk itself asks for the cell
    }
    lock.lock();
    Slot& s = slots_[k];
    s.set = std::move(set);
    s.error = std::move(error);
    s.loading = false;
    if (s.set) ++reads_;
    changed_.notify_all();
    evict_locked();
  }
}

// ---- walk ---------------------------------------------------------------------------------

std::vector<WalkFrame> walk(const Scene& scene, const std::string& directory, const CellManifest& manifest,
                            const std::vector<CameraPose>& path, const WalkOptions& options,
                            const std::function<void(const WalkFrame&, const FrameImage&, const FrameImage&)>& on_frame) {
  const HexGrid grid = manifest.grid();
  const bool references = options.reference_every > 0;
  RenderSet full;
  if (references) full = full_scene_set(scene);
  const double near = std::max(1e-3, 0.01 * manifest.eye_height);
  CellCache cache(scene, directory, manifest, options.prefetch);
  PerspectiveRasterizer raster;
  PerspectiveFrame scratch;
  FrameImage image_c, image_a, image_b;
  std::vector<WalkFrame> frames;
  HexCell previous{std::numeric_limits<int>::min(), 0};
  for (std::size_t k = 0; k < path.size(); ++k) {
    WalkFrame f;
    f.index = k;
    f.pose = path[k];
    f.cell = grid.cell_of(f.pose.position.x, f.pose.position.y);
    f.crossing = f.cell != previous;
    previous = f.cell;
    const PerspectiveView view = frame_view(f.pose, options.fov_degrees, options.resolution, near);
    const auto start = std::chrono::steady_clock::now();
    double read = 0;
    const std::shared_ptr<const RenderSet> set = cache.get(f.cell, &read);
    if (f.crossing) cache.prefetch_around(f.cell);
    f.faces_c = render_frame(*set, view, true, options.shading, options.textures, raster, scratch, image_c);
    f.ms_c = 1e3 * seconds_since(start);
    f.read_ms = 1e3 * read;
    f.image_hash = fnv1a(kFnvOffset, image_c.y.data(), image_c.y.size());
    image_a.y.clear();
    f.psnr = std::numeric_limits<double>::quiet_NaN();
    if (references && k % options.reference_every == 0) {
      auto t0 = std::chrono::steady_clock::now();
      f.faces_a = render_frame(full, view, false, options.shading, false, raster, scratch, image_a);
      f.ms_a = 1e3 * seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      f.faces_b = render_frame(full, view, true, options.shading, false, raster, scratch, image_b);
      f.ms_b = 1e3 * seconds_since(t0);
      f.psnr = psnr(image_a, image_c);
    }
    if (on_frame) on_frame(f, image_c, image_a);
    frames.push_back(f);
  }
  return frames;
}

}  // namespace visimp
