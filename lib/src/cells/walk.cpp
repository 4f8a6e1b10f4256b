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
// A fixed light, two-sided Lambert with an ambient floor; sky and ground are the background.
constexpr float kAmbient = 0.25f, kDiffuse = 0.75f;
constexpr std::uint8_t kBackground = 200;

std::array<float, 3> to_float(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}

float object_albedo(std::uint32_t object) {
  // A fixed grey per object, spread over [0.55, 0.95] so neighbours differ.
  std::uint64_t h = fnv1a(kFnvOffset, &object, sizeof object);
  return 0.55f + 0.4f * static_cast<float>(h % 1000) / 999.0f;
}

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
  BoundingBox box;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    for (const Vec3& p : scene.meshes[o.mesh].positions) box.extend(transform_point(o.transform, p));
  }
  const double cx = 0.5 * (box.min.x + box.max.x), cy = 0.5 * (box.min.y + box.max.y);
  const double ax = 0.35 * (box.max.x - box.min.x), ay = 0.35 * (box.max.y - box.min.y);
  std::vector<CameraPose> out;
  for (std::size_t k = 0; k < frames; ++k) {
    const double t = 2 * M_PI * static_cast<double>(k) / static_cast<double>(frames);
    const Vec3 p{cx + ax * std::cos(t), cy + ay * std::sin(t), eye_height};
    const double heading = std::atan2(ay * std::cos(t), -ax * std::sin(t)) + 30 * kDegree * std::sin(5 * t);
    out.push_back({p, {std::cos(heading), std::sin(heading), 0}});
  }
  return out;
}

void RenderSet::add(const Mesh& mesh, const std::vector<std::uint32_t>* subset, std::uint32_t object) {
  Group g;
  g.first_face = static_cast<std::uint32_t>(faces.size());
  // Only the vertices the faces use, in first-use order.
  std::vector<VertexIndex> remap(mesh.num_vertices(), ~VertexIndex{0});
  // Corner normals over all of the mesh's faces, also those left out (a culled subset of an
  // object shades as the whole object does), smoothed only across edges bending less than
  // kCreaseDegrees: a CAD part's sharp edges stay sharp however large its faces become.
  constexpr double kCreaseDegrees = 40;
  const double crease_cos = std::cos(kCreaseDegrees * kDegree);
  std::vector<Vec3> area(mesh.num_faces()), unit(mesh.num_faces());
  std::vector<std::uint32_t> first(mesh.num_vertices() + 1, 0), incident;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    area[f] = face_normal_unnormalized(mesh, mesh.faces[f]);
    const double length = norm(area[f]);
    unit[f] = length > 0 ? area[f] / length : Vec3{0, 0, 0};
    for (VertexIndex v : mesh.faces[f]) ++first[v + 1];
  }
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) first[v + 1] += first[v];
  incident.resize(first.back());
  {
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
      for (VertexIndex v : mesh.faces[f]) incident[fill[v]++] = static_cast<std::uint32_t>(f);
  }
  BoundingBox box;
  const std::size_t count = subset ? subset->size() : mesh.num_faces();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t fi = subset ? (*subset)[k] : k;
    const Face& f = mesh.faces[fi];
    Face g_face;
    std::array<std::array<float, 3>, 3> corners;
    for (int c = 0; c < 3; ++c) {
      const VertexIndex v = f[static_cast<std::size_t>(c)];
      VertexIndex& m = remap[v];
      if (m == ~VertexIndex{0}) {
        m = static_cast<VertexIndex>(positions.size());
        positions.push_back(to_float(mesh.positions[v]));
        box.extend(mesh.positions[v]);
      }
      g_face[static_cast<std::size_t>(c)] = m;
      Vec3 sum{0, 0, 0};
      for (std::uint32_t i = first[v]; i < first[v + 1]; ++i) {
        const std::uint32_t h = incident[i];
        if (dot(unit[h], unit[fi]) >= crease_cos) sum = sum + area[h];
      }
      const double length = norm(sum);
      corners[static_cast<std::size_t>(c)] = to_float(length > 0 ? sum / length : unit[fi]);
    }
    faces.push_back(g_face);
    corner_normals.push_back(corners);
  }
  g.faces = static_cast<std::uint32_t>(faces.size()) - g.first_face;
  g.centre = box.center();
  g.radius = g.faces ? 0.5 * box.diagonal() : 0;
  face_albedo.resize(faces.size(), object_albedo(object));
  groups.push_back(g);
}

void RenderSet::finish() {
  face_normals.assign(faces.size(), {0, 0, 0});
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& a = positions[faces[f][0]];
    const auto& b = positions[faces[f][1]];
    const auto& c = positions[faces[f][2]];
    const Vec3 n = cross(Vec3{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, Vec3{c[0] - a[0], c[1] - a[1], c[2] - a[2]});
    const double length = norm(n);
    if (length > 0) face_normals[f] = to_float(n / length);
  }
}

RenderSet full_scene_set(const Scene& scene) {
  RenderSet set;
  for (std::size_t i = 0; i < scene.objects.size(); ++i)
    set.add(scene.object_mesh(i), nullptr, static_cast<std::uint32_t>(i));
  set.finish();
  return set;
}

RenderSet cell_set(const Scene& scene, const CellLods& lods) {
  RenderSet set;
  for (const CellEntry& e : lods.entries) {
    if (e.kind == LodKind::full)
      set.add(scene.object_mesh(e.object), &e.faces, e.object);
    else
      set.add(e.mesh, nullptr, e.object);
  }
  set.finish();
  return set;
}

PerspectiveView frame_view(const CameraPose& pose, double fov_degrees, int resolution, double near) {
  return PerspectiveView::looking_at(pose.position, pose.position + pose.direction, fov_degrees, resolution, near);
}

std::size_t render_frame(const RenderSet& set, const PerspectiveView& view, bool cull, Shading shading,
                         PerspectiveRasterizer& raster, PerspectiveFrame& frame, FrameImage& out) {
  // Per-group frustum test: the sphere against the four side planes and the near plane.
  const double t = view.tan_half_fov, plane_norm = std::sqrt(1 + t * t);
  std::vector<std::uint32_t> subset;
  std::size_t drawn = 0;
  bool all = true;
  for (const RenderSet::Group& g : set.groups) {
    bool keep = g.faces > 0;
    if (keep && cull) {
      const Vec3 p = g.centre - view.eye;
      const double x = dot(p, view.right), y = dot(p, view.up), z = dot(p, view.forward);
      keep = z + g.radius >= view.near && (x - t * z) / plane_norm <= g.radius &&
             (-x - t * z) / plane_norm <= g.radius && (y - t * z) / plane_norm <= g.radius &&
             (-y - t * z) / plane_norm <= g.radius;
    }
    if (!keep) {
      all = false;
      continue;
    }
    drawn += g.faces;
    for (std::uint32_t f = g.first_face; f < g.first_face + g.faces; ++f) subset.push_back(f);
  }
  raster.draw(set.positions, set.faces, all ? nullptr : &subset, view, frame);
  const int size = view.resolution;
  out.resolution = size;
  out.y.assign(static_cast<std::size_t>(size) * size, kBackground);
  const Vec3 light_d = Vec3{0.3, 0.5, 0.8} / norm(Vec3{0.3, 0.5, 0.8});
  const float light[3] = {static_cast<float>(light_d.x), static_cast<float>(light_d.y), static_cast<float>(light_d.z)};
  const auto eye = to_float(view.eye);
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < size; ++i) {
      const std::size_t p = static_cast<std::size_t>(j) * size + i;
      const std::uint32_t id = frame.ids[p];
      if (id == 0) continue;
      const std::uint32_t f = id - 1;
      std::array<float, 3> n = set.face_normals[f];
      if (shading == Shading::smooth) {
        // Barycentrics of the pixel's ray in the triangle (Möller–Trumbore), then the
        // interpolated vertex normal.
        const Vec3 dir = view.pixel_ray(i, j);
        const float d[3] = {static_cast<float>(dir.x), static_cast<float>(dir.y), static_cast<float>(dir.z)};
        const auto& a = set.positions[set.faces[f][0]];
        const auto& b = set.positions[set.faces[f][1]];
        const auto& c = set.positions[set.faces[f][2]];
        const float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const float s[3] = {eye[0] - a[0], eye[1] - a[1], eye[2] - a[2]};
        const float pv[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
        const float det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (std::abs(det) > 0) {
          const float q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
          float u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
          float v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
          u = std::clamp(u, 0.0f, 1.0f);
          v = std::clamp(v, 0.0f, 1.0f - u);
          const auto& na = set.corner_normals[f][0];
          const auto& nb = set.corner_normals[f][1];
          const auto& nc = set.corner_normals[f][2];
          std::array<float, 3> m;
          for (int k = 0; k < 3; ++k)
            m[static_cast<std::size_t>(k)] = (1 - u - v) * na[static_cast<std::size_t>(k)] +
                                             u * nb[static_cast<std::size_t>(k)] + v * nc[static_cast<std::size_t>(k)];
          const float length = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
          if (length > 0) n = {m[0] / length, m[1] / length, m[2] / length};
        }
      }
      const float lambert = std::abs(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
      const float grey = 255.0f * set.face_albedo[f] * (kAmbient + kDiffuse * lambert);
      out.y[p] = static_cast<std::uint8_t>(std::clamp(grey + 0.5f, 0.0f, 255.0f));
    }
  }
  return drawn;
}

double psnr(const FrameImage& reference, const FrameImage& approx) {
  if (reference.y.size() != approx.y.size() || reference.y.empty())
    throw UsageError("psnr: images of different sizes");
  double sum = 0;
  for (std::size_t p = 0; p < reference.y.size(); ++p) {
    const double d = static_cast<double>(reference.y[p]) - approx.y[p];
    sum += d * d;
  }
  const double mse = sum / static_cast<double>(reference.y.size());
  return mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
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
    f.faces_c = render_frame(*set, view, true, options.shading, raster, scratch, image_c);
    f.ms_c = 1e3 * seconds_since(start);
    f.read_ms = 1e3 * read;
    f.image_hash = fnv1a(kFnvOffset, image_c.y.data(), image_c.y.size());
    image_a.y.clear();
    f.psnr = std::numeric_limits<double>::quiet_NaN();
    if (references && k % options.reference_every == 0) {
      auto t0 = std::chrono::steady_clock::now();
      f.faces_a = render_frame(full, view, false, options.shading, raster, scratch, image_a);
      f.ms_a = 1e3 * seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      f.faces_b = render_frame(full, view, true, options.shading, raster, scratch, image_b);
      f.ms_b = 1e3 * seconds_since(t0);
      f.psnr = psnr(image_a, image_c);
    }
    if (on_frame) on_frame(f, image_c, image_a);
    frames.push_back(f);
  }
  return frames;
}

}  // namespace visimp
