// Building the visibility field: slab placement, 81-ray pre-filtered samples, the solid
// interior grid (see field.h).
#include "visimp/field/field.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "visimp/core/errors.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/parallel.h"
#include "visimp/render/ray_caster.h"
#include "visimp/render/renderer.h"

namespace visimp {

void check_options(const FieldOptions& o, std::size_t faces) {
  check_options(o.cells, faces);
  auto range = [](const int& value, const char* name, int lo, int hi) {
    if (value < lo || value > hi) {
      throw OptionError(&value, name, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
  };
  range(o.uv, "FieldOptions::uv", kMinSamples, kMaxSamples);
  range(o.st, "FieldOptions::st", kMinSamples, kMaxSamples);
  range(o.ids, "FieldOptions::ids", 1, kMaxIds);
  range(o.layers, "FieldOptions::layers", 1, kMaxLayers);
  if (o.slabs != 1 && o.slabs != 6) throw OptionError(&o.slabs, "FieldOptions::slabs", "must be 6 or 1");
  if (o.threads > kMaxThreads) {
    throw OptionError(&o.threads, "FieldOptions::threads", "must be at most " + std::to_string(kMaxThreads));
  }
}

std::vector<OptionSpec> describe_options(FieldOptions& o) {
  return {option_spec("--grid", "N", o.cells.grid, "cells along the longest side of each object's grid, 1..255"),
          option_spec("--uv", "N", o.uv, "uv samples per side (directions), 2..64"),
          option_spec("--st", "N", o.st, "st samples per side (positions), 2..64"),
          option_spec("--ids", "N", o.ids, "cell ids kept per sample, 1..8"),
          option_spec("--slabs", "6|1", o.slabs, "one slab per side of the box, or the paper's single +z slab"),
          option_spec("--layers", "N", o.layers, "start planes per slab for viewpoints inside the box, 1..16"),
          option_spec("--threads", "N", o.threads, "worker threads (0 = one per hardware thread)")};
}

Vec3 Slab::direction(double u, double v) const {
  double d[3];
  d[axis] = -side;
  d[s_axis()] = u;
  d[t_axis()] = v;
  return {d[0], d[1], d[2]};
}

namespace {}  // namespace

std::vector<Slab> place_slabs(const BoundingBox& box, int slabs, int layers) {
  std::vector<Slab> out;
  const double diagonal = std::max(box.diagonal(), 1e-30);
  const double margin = 1e-3 * diagonal;  // lines grazing the box still fall inside the rectangles
  for (int axis = 0; axis < 3; ++axis) {
    for (int side : {1, -1}) {
      if (slabs == 1 && !(axis == 2 && side == 1)) continue;
      Slab s;
      s.axis = axis;
      s.side = side;
      const double lo = box.min[axis], hi = box.max[axis];
      const double half_depth = 0.5 * (hi - lo);
      s.plane = 0.5 * (lo + hi);
      s.s_range = {box.min[s.s_axis()] - half_depth - margin, box.max[s.s_axis()] + half_depth + margin};
      s.t_range = {box.min[s.t_axis()] - half_depth - margin, box.max[s.t_axis()] + half_depth + margin};
      const double entry = side > 0 ? hi + margin : lo - margin;
      for (int k = 0; k < layers; ++k) s.starts.push_back(entry - side * (2 * half_depth + margin) * k / layers);
      out.push_back(s);
    }
  }
  return out;
}

void rank_cells(std::vector<std::uint32_t>& hits, int keep, std::uint32_t* out) {
  std::sort(hits.begin(), hits.end());
  // (count, id) of each distinct hit; the most frequent first, ties to the smaller id.
  std::array<std::pair<int, std::uint32_t>, 81> runs;
  std::size_t n = 0;
  for (std::size_t i = 0; i < hits.size();) {
    std::size_t j = i;
    while (j < hits.size() && hits[j] == hits[i]) ++j;
    if (hits[i] != kNoCell && n < runs.size()) runs[n++] = {static_cast<int>(j - i), hits[i]};
    i = j;
  }
  std::sort(runs.begin(), runs.begin() + static_cast<std::ptrdiff_t>(n),
            [](const auto& a, const auto& b) { return a.first != b.first ? a.first > b.first : a.second < b.second; });
  for (int r = 0; r < keep; ++r)
    out[r] = static_cast<std::size_t>(r) < n ? runs[static_cast<std::size_t>(r)].second + 1 : 0;
}

std::size_t VisibilityField::sample_bytes() const {
  std::size_t entries = 0;
  for (const auto& slab : samples) {
    for (const auto& layer : slab) entries += layer.size();
  }
  return entries * static_cast<std::size_t>(id_width());
}

bool VisibilityField::inside_solid(const Vec3& p) const {
  if (interior.empty() || box.empty()) return false;
  int c[3];
  for (int a = 0; a < 3; ++a) {
    const double lo = box.min[a], hi = box.max[a];
    const double x = p[a];
    if (!(x >= lo && x <= hi)) return false;
    c[a] = hi > lo ? std::min(kOccupancy - 1, static_cast<int>((x - lo) / (hi - lo) * kOccupancy)) : 0;
  }
  const std::size_t bit = (static_cast<std::size_t>(c[2]) * kOccupancy + c[1]) * kOccupancy + c[0];
  return (interior[bit / 8] >> (bit % 8)) & 1;
}

VisibilityField build_field(const Mesh& mesh, const FieldOptions& options, RenderObserver* observer) {
  const auto start = std::chrono::steady_clock::now();
  check_options(options, mesh.num_faces());
  if (mesh.num_faces() == 0) throw InvalidMeshError("the mesh has no faces: a visibility field needs some");
  VisibilityField field;
  field.mesh_hash = hash_mesh(mesh);
  field.faces = mesh.num_faces();
  field.vertices = mesh.num_vertices();
  field.options = options;
  field.options.cells.face_objects.clear();
  field.box = bounding_box(mesh);
  field.cells = partition_cells(mesh, options.cells);
  field.slabs = place_slabs(field.box, options.slabs, options.layers);

  // Ray casting in float relative to the box centre (precise far from the origin).
  const Vec3 center = field.box.center();
  std::vector<std::array<float, 3>> relative(mesh.num_vertices());
  for (std::size_t i = 0; i < relative.size(); ++i) {
    const Vec3 p = mesh.positions[i] - center;
    relative[i] = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  }
  const RayCaster caster(relative, mesh.faces, static_cast<unsigned>(options.threads));

  const int uv = options.uv, st = options.st, ids = options.ids;
  const std::size_t per_layer = field.samples_per_layer();
  field.samples.resize(field.slabs.size());
  for (auto& slab : field.samples)
    slab.assign(static_cast<std::size_t>(options.layers),
                std::vector<std::uint32_t>(per_layer * static_cast<std::size_t>(ids)));

  // One job per (slab, layer, iu, iv): st·st samples of 81 rays each.
  const std::size_t jobs =
      field.slabs.size() * static_cast<std::size_t>(options.layers) * static_cast<std::size_t>(uv) * uv;
  const unsigned workers = worker_count(static_cast<unsigned>(options.threads), jobs);
  std::vector<std::vector<float>> origins(workers), directions(workers);
  std::vector<std::vector<std::uint32_t>> hits(workers), cells(workers);
  const std::size_t rays_per_job = static_cast<std::size_t>(st) * st * 81;
  parallel_for(
      0, jobs, workers,
      [&](unsigned w, std::size_t job) {
        const std::size_t per_slab_layer = static_cast<std::size_t>(uv) * uv;
        const std::size_t slab_index = job / (static_cast<std::size_t>(options.layers) * per_slab_layer);
        const std::size_t layer = (job / per_slab_layer) % static_cast<std::size_t>(options.layers);
        const int iu = static_cast<int>((job / uv) % uv), iv = static_cast<int>(job % uv);
        const Slab& slab = field.slabs[slab_index];
        const double start_plane = slab.starts[layer] - center[slab.axis];
        const double plane = slab.plane - center[slab.axis];
        const double s0 = slab.s_range[0] - center[slab.s_axis()], t0 = slab.t_range[0] - center[slab.t_axis()];
        const double ds = (slab.s_range[1] - slab.s_range[0]) / st, dt = (slab.t_range[1] - slab.t_range[0]) / st;
        auto& org = origins[w];
        auto& dir = directions[w];
        org.resize(rays_per_job * 3);
        dir.resize(rays_per_job * 3);
        std::size_t ray = 0;
        {
          for (int is = 0; is < st; ++is) {
            for (int it = 0; it < st; ++it) {
              // 3×3 positions in the uv cell times 3×3 in the st cell (§3.3).
              for (int a = 0; a < 9; ++a) {
                const double u = -1 + (iu + (a % 3 + 0.5) / 3) * 2.0 / uv;
                const double v = -1 + (iv + (a / 3 + 0.5) / 3) * 2.0 / uv;
                const Vec3 d = slab.direction(u, v);
                for (int b = 0; b < 9; ++b) {
                  double p[3];
                  p[slab.axis] = plane;
                  p[slab.s_axis()] = s0 + (is + (b % 3 + 0.5) / 3) * ds;
                  p[slab.t_axis()] = t0 + (it + (b / 3 + 0.5) / 3) * dt;
                  // Move along the line to the start plane: the ray begins where the viewer's would enter.
                  const double lambda = (start_plane - plane) / (-slab.side);
                  org[3 * ray] = static_cast<float>(p[0] + lambda * d.x);
                  org[3 * ray + 1] = static_cast<float>(p[1] + lambda * d.y);
                  org[3 * ray + 2] = static_cast<float>(p[2] + lambda * d.z);
                  dir[3 * ray] = static_cast<float>(d.x);
                  dir[3 * ray + 1] = static_cast<float>(d.y);
                  dir[3 * ray + 2] = static_cast<float>(d.z);
                  ++ray;
                }
              }
            }
          }
        }
        hits[w].resize(rays_per_job);
        caster.first_hits(org.data(), dir.data(), rays_per_job, hits[w].data());
        std::vector<std::uint32_t>& out = field.samples[slab_index][layer];
        auto& sample_cells = cells[w];
        for (std::size_t k = 0; k < static_cast<std::size_t>(st) * st; ++k) {
          sample_cells.assign(hits[w].begin() + static_cast<std::ptrdiff_t>(81 * k),
                              hits[w].begin() + static_cast<std::ptrdiff_t>(81 * (k + 1)));
          for (std::uint32_t& h : sample_cells) h = h == RayCaster::kNoHit ? kNoCell : field.cells.face_cell[h];
          const std::size_t index = (static_cast<std::size_t>(iu) * uv + iv) * st * st + k;
          rank_cells(sample_cells, ids, &out[index * static_cast<std::size_t>(ids)]);
        }
      },
      observer ? std::function<void(double)>([observer](double f) { observer->on_render_progress(0.95 * f); })
               : std::function<void(double)>());
  field.rays = static_cast<std::uint64_t>(jobs) * rays_per_job;

  // Solid interior by ray parity along the six axis directions, majority vote: a viewpoint
  // there is inside closed geometry and the field is refused for it.
  constexpr int n = VisibilityField::kOccupancy;
  field.interior.assign(n * n * n / 8, 0);
  const Vec3 extent = field.box.max - field.box.min;
  parallel_for(
      0, static_cast<std::size_t>(n) * n, worker_count(static_cast<unsigned>(options.threads), n * n),
      [&](unsigned, std::size_t row) {
        const int cz = static_cast<int>(row / n), cy = static_cast<int>(row % n);
        for (int cx = 0; cx < n; ++cx) {
          const Vec3 p = field.box.min - center +
                         Vec3{extent.x * (cx + 0.5) / n, extent.y * (cy + 0.5) / n, extent.z * (cz + 0.5) / n};
          const std::array<float, 3> o{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
          int odd = 0;
          for (int a = 0; a < 6; ++a) {
            std::array<float, 3> d{0, 0, 0};
            d[static_cast<std::size_t>(a / 2)] = a % 2 ? -1.0f : 1.0f;
            odd += static_cast<int>(caster.crossings(o, d) % 2);
          }
          if (odd >= 4) {
            const std::size_t bit = (static_cast<std::size_t>(cz) * n + cy) * n + cx;
            // Rows are disjoint per job but share bytes only within a row (n is a multiple of 8).
            field.interior[bit / 8] = static_cast<std::uint8_t>(field.interior[bit / 8] | (1u << (bit % 8)));
          }
        }
      });
  if (observer) observer->on_render_progress(1.0);
  field.seconds_build = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return field;
}

void check_field_matches(const VisibilityField& field, const Mesh& mesh, const std::string& field_path,
                         const std::string& mesh_path) {
  if (field.mesh_hash != hash_mesh(mesh) || field.faces != mesh.num_faces()) {
    throw IoError(field_path, "was built for another mesh than " + mesh_path + " (content hash differs)");
  }
}

}  // namespace visimp
