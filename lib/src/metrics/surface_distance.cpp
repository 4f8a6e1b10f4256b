#include "visimp/metrics/surface_distance.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <vector>

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/parallel.h"
#include "visimp/core/spatial_order.h"
#include "closest_triangle_index.h"

#include "visimp/core/portable_random.h"
#include "visimp/core/stopwatch.h"

namespace visimp {
namespace {

using Random = SplitMix64;

// One generator per face or edge, seeded from (seed, index): the samples of an element never
// depend on which worker draws them or in which order.
Random element_random(std::uint64_t seed, std::uint64_t kind, std::size_t index) {
  return Random(seed * 0xd1b54a32d192ed03ull ^ (kind << 62) ^ (std::uint64_t{index} * 0x9e3779b97f4a7c15ull));
}
constexpr std::uint64_t kFaceStream = 1, kEdgeStream = 2;

// Where the samples of one surface go, decided up front (cheap, serial) so that the samples
// themselves can be drawn and measured in parallel without ever being stored.
struct SamplePlan {
  std::vector<VertexIndex> vertices;        // vertices used by a face: one sample each
  std::vector<std::uint64_t> edges;         // distinct edges (min << 32 | max)
  std::vector<std::uint32_t> edge_samples;  // per edge: points spread along it (for the max)
  std::vector<double> area;                 // per face; 0 for degenerate faces
  std::vector<std::uint32_t> face_samples;  // per face: samples on it
  std::vector<std::size_t> face_offset;     // per face + 1: prefix sums of face_samples
  std::vector<std::uint32_t> face_order;    // the order faces are measured in (spatial)
  FaceSampling sampling = FaceSampling::random;
  std::uint64_t seed = 0;
  std::size_t edge_total = 0;
};

SamplePlan plan_samples(const Mesh& m, std::size_t count, std::size_t edge_count, std::uint64_t seed,
                        FaceSampling sampling, unsigned threads) {
  SamplePlan plan;
  plan.sampling = sampling;
  plan.seed = seed;
  std::vector<char> used(m.num_vertices(), 0);
  for (const Face& f : m.faces)
    for (VertexIndex v : f) used[v] = 1;
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (used[v]) plan.vertices.push_back(static_cast<VertexIndex>(v));
  double total = 0;
  plan.area.resize(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    plan.area[f] = is_degenerate(m, m.faces[f]) ? 0.0 : 0.5 * norm(face_normal_unnormalized(m, m.faces[f]));
    total += plan.area[f];
  }
  plan.face_samples.assign(m.num_faces(), 0);
  plan.face_offset.assign(m.num_faces() + 1, 0);
  if (!(total > 0)) return plan;
  // Edges: floor(edge_count·share + u) points each, share by length.
  plan.edges.reserve(m.num_faces() * 3);
  for (const Face& f : m.faces)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = f[k], b = f[(k + 1) % 3];
      if (a != b) plan.edges.push_back((std::uint64_t{std::min(a, b)} << 32) | std::max(a, b));
    }
  std::sort(plan.edges.begin(), plan.edges.end());
  plan.edges.erase(std::unique(plan.edges.begin(), plan.edges.end()), plan.edges.end());
  std::vector<double> length(plan.edges.size());
  double total_length = 0;
  for (std::size_t e = 0; e < plan.edges.size(); ++e) {
    length[e] = norm(m.positions[plan.edges[e] >> 32] - m.positions[plan.edges[e] & 0xffffffffu]);
    total_length += length[e];
  }
  plan.edge_samples.assign(plan.edges.size(), 0);
  if (total_length > 0) {
    for (std::size_t e = 0; e < plan.edges.size(); ++e) {
      const double u = element_random(seed, kEdgeStream, e).uniform();
      plan.edge_samples[e] = static_cast<std::uint32_t>(std::floor(double(edge_count) * length[e] / total_length + u));
      plan.edge_total += plan.edge_samples[e];
    }
  }
  // Faces: floor(count·share + u) samples each (expected count·share), each carrying an equal
  // part of the face's area, so sums over samples estimate integrals over the surface.
  // Stratified sampling rounds each face's count to a square (see draw_face_samples).
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    if (plan.area[f] > 0) {
      const double u = element_random(seed, kFaceStream, f).uniform();
      auto n = static_cast<std::size_t>(std::floor(double(count) * plan.area[f] / total + u));
      if (sampling == FaceSampling::stratified && n > 0) {
        const auto k = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(std::sqrt(double(n)))));
        n = k * k;
      }
      plan.face_samples[f] = static_cast<std::uint32_t>(std::min<std::size_t>(n, 0xffffffffu));
    }
    plan.face_offset[f + 1] = plan.face_offset[f] + plan.face_samples[f];
  }
  plan.face_order = spatial_face_order(m, threads);  // the same order for any thread count
  return plan;
}

// The face's samples, appended to `out`, drawn from the face's own generator (after the draw
// that decided their number).
void draw_face_samples(const Mesh& m, const SamplePlan& plan, std::size_t f, std::vector<Vec3>& out) {
  const std::size_t n = plan.face_samples[f];
  if (n == 0) return;
  Random rng = element_random(plan.seed, kFaceStream, f);
  rng.uniform();
  const Vec3 &a = m.positions[m.faces[f][0]], &b = m.positions[m.faces[f][1]], &c = m.positions[m.faces[f][2]];
  if (plan.sampling == FaceSampling::random) {
    // Drawn in any order, then visited along a Morton curve of (r1, r2), so that each
    // sample's closest-point hint comes from a neighbour (3x faster queries on big faces).
    struct Draw {
      std::uint32_t key;
      double r1, r2;
    };
    std::vector<Draw> draws(n);
    for (Draw& d : draws) {
      d.r1 = std::sqrt(rng.uniform());
      d.r2 = rng.uniform();
      d.key = morton_code({d.r1, d.r2, 0.0});
    }
    if (n > 2) std::stable_sort(draws.begin(), draws.end(), [](const Draw& x, const Draw& y) { return x.key < y.key; });
    for (const Draw& d : draws) out.push_back(a * (1 - d.r1) + b * (d.r1 * (1 - d.r2)) + c * (d.r1 * d.r2));
    return;
  }
  // Stratified: split the face into k² congruent cells and put one uniform point in each.
  // In barycentric units of 1/k, cell (i, j) is the upright triangle S ∈ [i, i+1],
  // T ∈ [j, j+1], S + T ≤ i + j + 1, or its inverted neighbour.
  const auto k = static_cast<std::size_t>(std::lround(std::sqrt(double(n))));
  const double kk = double(k);
  auto emit = [&](double S, double T) { out.push_back(a * (1 - (S + T) / kk) + b * (S / kk) + c * (T / kk)); };
  for (std::size_t i = 0; i < k; ++i) {
    for (std::size_t j = 0; i + j < k; ++j) {
      double u = rng.uniform(), v = rng.uniform();
      if (u + v > 1) {  // fold the unit square onto the unit triangle
        u = 1 - u;
        v = 1 - v;
      }
      emit(double(i) + u, double(j) + v);
      if (i + j + 1 < k) emit(double(i) + 1 - u, double(j) + 1 - v);
    }
  }
}

// Distances from one surface's samples to the other surface. Face-sample distances are kept
// in face order (face_offset), the weight of each being area / face_samples of its face.
struct SampleDistances {
  std::vector<double> vertex;  // per plan.vertices entry, when asked for (error maps)
  std::vector<double> face;    // per face sample
  double vertex_max = 0, edge_max = 0;
};

std::unique_ptr<const ClosestTriangleIndex> build_index(const Mesh& to, int threads, double& seconds_index) {
  const auto t = std::chrono::steady_clock::now();
  auto index = std::make_unique<const ClosestTriangleIndex>(to, threads > 0 ? unsigned(threads) : 0u);
  if (index->empty()) throw InvalidMeshError("surface distance: a mesh has no non-degenerate face");
  seconds_index += seconds_since(t);
  return index;
}

// Vertex and edge samples count only through their largest distance (and the vertices' own
// values when `vertex_values`, for error maps): each block keeps a running maximum, and a
// sample whose hint triangle is already within it needs no search (squared_distance_past).
// The maxima are exact, so the results are those of one full query per sample.
SampleDistances measure(const Mesh& from, const SamplePlan& plan, const ClosestTriangleIndex& index, int threads,
                        bool vertex_values, double& seconds_queries) {
  const auto t = std::chrono::steady_clock::now();
  SampleDistances d;
  if (vertex_values) d.vertex.resize(plan.vertices.size());
  d.face.resize(plan.face_offset.back());
  // Work items: blocks of vertices, of edges and of faces, in that order. Consecutive samples
  // lie close together, so each query starts from the previous answer (see the index).
  constexpr std::size_t kBlock = 512;
  const std::size_t vertex_blocks = (plan.vertices.size() + kBlock - 1) / kBlock;
  const std::size_t edge_blocks = (plan.edges.size() + kBlock - 1) / kBlock;
  const std::size_t face_blocks = (from.num_faces() + kBlock - 1) / kBlock;
  std::vector<double> vertex_block_max(vertex_blocks, 0.0), edge_block_max(edge_blocks, 0.0);
  const unsigned workers =
      worker_count(threads > 0 ? unsigned(threads) : 0u, vertex_blocks + edge_blocks + face_blocks);
  parallel_for(0, vertex_blocks + edge_blocks + face_blocks, workers, [&](unsigned, std::size_t item) {
    std::uint32_t hint = ClosestTriangleIndex::kNoHint;
    if (item < vertex_blocks) {
      const std::size_t end = std::min(plan.vertices.size(), (item + 1) * kBlock);
      double max = 0;
      if (vertex_values) {
        for (std::size_t i = item * kBlock; i < end; ++i) {
          d.vertex[i] = std::sqrt(index.squared_distance(from.positions[plan.vertices[i]], hint));
          max = std::max(max, d.vertex[i]);
        }
      } else {
        for (std::size_t i = item * kBlock; i < end; ++i)
          max = std::max(max, index.squared_distance_past(from.positions[plan.vertices[i]], hint, max));
        max = std::sqrt(max);
      }
      vertex_block_max[item] = max;
      return;
    }
    item -= vertex_blocks;
    if (item < edge_blocks) {
      double max = 0;
      for (std::size_t e = item * kBlock; e < std::min(plan.edges.size(), (item + 1) * kBlock); ++e) {
        const Vec3 &a = from.positions[plan.edges[e] >> 32], &b = from.positions[plan.edges[e] & 0xffffffffu];
        Random rng = element_random(plan.seed, kEdgeStream, e);
        rng.uniform();
        const std::uint32_t n = plan.edge_samples[e];
        for (std::uint32_t i = 0; i < n; ++i) {
          const double s = (double(i) + rng.uniform()) / double(n);
          max = std::max(max, index.squared_distance_past(a * (1 - s) + b * s, hint, max));
        }
      }
      edge_block_max[item] = std::sqrt(max);
      return;
    }
    item -= edge_blocks;
    std::vector<Vec3> points;
    for (std::size_t i = item * kBlock; i < std::min(from.num_faces(), (item + 1) * kBlock); ++i) {
      const std::size_t f = plan.face_order[i];
      points.clear();
      draw_face_samples(from, plan, f, points);
      double* out = d.face.data() + plan.face_offset[f];
      index.squared_distances(points.data(), points.size(), out, hint);
      for (std::size_t s = 0; s < points.size(); ++s) out[s] = std::sqrt(out[s]);
    }
  });
  for (double m : vertex_block_max) d.vertex_max = std::max(d.vertex_max, m);
  for (double m : edge_block_max) d.edge_max = std::max(d.edge_max, m);
  seconds_queries += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  return d;
}

DirectedDistance summarize(const SamplePlan& plan, const SampleDistances& distance, std::size_t bins,
                           double& weighted_sq_sum, double& weight_sum) {
  DirectedDistance d;
  double sum = 0, sq = 0, w = 0;
  d.max = std::max(distance.vertex_max, distance.edge_max);
  const std::size_t faces = plan.face_samples.size();
  for (std::size_t f = 0; f < faces; ++f) {  // serial: same rounding for any thread count
    if (plan.face_samples[f] == 0) continue;
    const double weight = plan.area[f] / double(plan.face_samples[f]);
    for (std::size_t i = plan.face_offset[f]; i < plan.face_offset[f + 1]; ++i) {
      const double x = distance.face[i];
      d.max = std::max(d.max, x);
      sum += weight * x;
      sq += weight * x * x;
    }
    w += plan.area[f];
  }
  d.face_samples = distance.face.size();
  d.samples = plan.vertices.size() + plan.edge_total + d.face_samples;
  d.area = w;
  d.mean = w > 0 ? sum / w : 0;
  d.rms = w > 0 ? std::sqrt(sq / w) : 0;
  d.histogram.assign(std::max<std::size_t>(bins, 1), 0.0);
  if (w > 0) {
    for (std::size_t f = 0; f < faces; ++f) {
      if (plan.face_samples[f] == 0) continue;
      const double share = plan.area[f] / double(plan.face_samples[f]) / w;
      for (std::size_t i = plan.face_offset[f]; i < plan.face_offset[f + 1]; ++i) {
        const double x = d.max > 0 ? distance.face[i] / d.max : 0.0;
        d.histogram[std::min(d.histogram.size() - 1, static_cast<std::size_t>(x * double(d.histogram.size())))] +=
            share;
      }
    }
  }
  weighted_sq_sum += sq;
  weight_sum += w;
  return d;
}

VisibleDistance summarize_visible(const SamplePlan& plan, const SampleDistances& distance,
                                  const std::vector<float>& face_visibility) {
  VisibleDistance v;
  double sum = 0, sq = 0, w = 0;
  for (std::size_t f = 0; f < plan.face_samples.size(); ++f) {
    if (plan.face_samples[f] == 0) continue;
    const double visibility = face_visibility[f];
    const double weight = plan.area[f] / double(plan.face_samples[f]) * visibility;
    for (std::size_t i = plan.face_offset[f]; i < plan.face_offset[f + 1]; ++i) {
      const double x = distance.face[i];
      if (visibility > 0) v.max = std::max(v.max, x);
      sum += weight * x;
      sq += weight * x * x;
    }
    w += plan.area[f] * visibility;
  }
  v.visible_area = w;
  v.mean = w > 0 ? sum / w : 0;
  v.rms = w > 0 ? std::sqrt(sq / w) : 0;
  return v;
}

}  // namespace

// What a SurfaceDistanceReference keeps of A between calls.
struct SurfaceDistanceReference::Cache {
  std::mutex mutex;
  std::unique_ptr<const ClosestTriangleIndex> index;
  double diagonal = 0;
  // A's sample plan and what it was made for.
  std::unique_ptr<const SamplePlan> plan;
  std::size_t count = 0, edges = 0;
  std::uint64_t seed = 0;
  FaceSampling sampling = FaceSampling::random;
};

namespace {

void check_face_visibility(const Mesh& a, const SurfaceDistanceOptions& options) {
  if (!options.face_visibility.empty() && options.face_visibility.size() != a.num_faces()) {
    throw InvalidMeshError("SurfaceDistanceOptions::face_visibility has " +
                           std::to_string(options.face_visibility.size()) + " values for " +
                           std::to_string(a.num_faces()) + " faces of A");
  }
  for (const float v : options.face_visibility) {
    if (!(v >= 0 && v <= 1))
      throw InvalidMeshError("SurfaceDistanceOptions::face_visibility holds a value outside [0, 1]");
  }
}

// The whole measurement; with `cache` A's index, plan and diagonal come from it (made on
// first use), and the numbers are the same as without.
SurfaceDistance distance_between(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options,
                                 SurfaceDistanceReference::Cache* cache) {
  const auto start = std::chrono::steady_clock::now();
  const bool weighted = !options.face_visibility.empty();
  check_face_visibility(a, options);
  std::size_t count = options.samples ? options.samples : 10 * std::max(a.num_faces(), b.num_faces());
  if (options.density > 0) {
    count = static_cast<std::size_t>(std::ceil(options.density * std::max(surface_area(a), surface_area(b))));
  }
  const std::size_t edges = options.edge_samples ? options.edge_samples : std::max(a.num_faces(), b.num_faces());
  SurfaceDistance r;
  std::unique_ptr<const SamplePlan> own_plan;
  std::unique_ptr<const ClosestTriangleIndex> own_index;
  const SamplePlan* on_a = nullptr;
  const ClosestTriangleIndex* index_of_a = nullptr;
  std::unique_lock<std::mutex> lock;
  auto t = std::chrono::steady_clock::now();
  const unsigned sort_threads = options.threads > 0 ? unsigned(options.threads) : 0u;
  if (cache != nullptr) {
    lock = std::unique_lock<std::mutex>(cache->mutex);
    const bool same_plan = cache->plan && cache->count == count && cache->edges == edges &&
                           cache->seed == options.seed && cache->sampling == options.sampling;
    if (!same_plan) {
      cache->plan = std::make_unique<const SamplePlan>(
          plan_samples(a, count, edges, options.seed, options.sampling, sort_threads));
      cache->count = count;
      cache->edges = edges;
      cache->seed = options.seed;
      cache->sampling = options.sampling;
    }
    on_a = cache->plan.get();
  } else {
    own_plan = std::make_unique<const SamplePlan>(plan_samples(a, count, edges, options.seed, options.sampling, sort_threads));
    on_a = own_plan.get();
  }
  const SamplePlan on_b = plan_samples(b, count, edges, options.seed + 1, options.sampling, sort_threads);
  r.seconds_sampling = seconds_since(t);
  SampleDistances from_a;
  {  // one index at a time when nothing is kept: the larger mesh's is the largest allocation
    const std::unique_ptr<const ClosestTriangleIndex> index_of_b = build_index(b, options.threads, r.seconds_index);
    from_a = measure(a, *on_a, *index_of_b, options.threads, options.vertex_errors, r.seconds_queries);
  }
  if (cache != nullptr) {
    if (!cache->index) cache->index = build_index(a, options.threads, r.seconds_index);
    index_of_a = cache->index.get();
  } else {
    own_index = build_index(a, options.threads, r.seconds_index);
    index_of_a = own_index.get();
  }
  const SampleDistances from_b = measure(b, on_b, *index_of_a, options.threads, false, r.seconds_queries);
  double sq = 0, w = 0;
  r.a_to_b = summarize(*on_a, from_a, options.histogram_bins, sq, w);
  r.b_to_a = summarize(on_b, from_b, options.histogram_bins, sq, w);
  r.hausdorff = std::max(r.a_to_b.max, r.b_to_a.max);
  r.rms = w > 0 ? std::sqrt(sq / w) : 0;
  if (cache != nullptr) {
    if (cache->diagonal == 0) cache->diagonal = bounding_box(a).diagonal();
    r.diagonal = cache->diagonal;
  } else {
    r.diagonal = bounding_box(a).diagonal();
  }
  if (weighted) r.visible = summarize_visible(*on_a, from_a, options.face_visibility);
  if (options.vertex_errors) {
    r.vertex_error.assign(a.num_vertices(), 0.0f);
    r.face_error.assign(a.num_faces(), 0.0f);
    for (std::size_t i = 0; i < on_a->vertices.size(); ++i)
      r.vertex_error[on_a->vertices[i]] = static_cast<float>(from_a.vertex[i]);
    for (std::size_t f = 0; f < a.num_faces(); ++f)
      for (std::size_t i = on_a->face_offset[f]; i < on_a->face_offset[f + 1]; ++i)
        r.face_error[f] = std::max(r.face_error[f], static_cast<float>(from_a.face[i]));
  }
  r.seconds = seconds_since(start);
  return r;
}

}  // namespace

SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options) {
  return distance_between(a, b, options, nullptr);
}

SurfaceDistanceReference::SurfaceDistanceReference(const Mesh& a) : a_(a), cache_(std::make_unique<Cache>()) {}
SurfaceDistanceReference::~SurfaceDistanceReference() = default;

SurfaceDistance SurfaceDistanceReference::distance_to(const Mesh& b, const SurfaceDistanceOptions& options) const {
  return distance_between(a_, b, options, cache_.get());
}

}  // namespace visimp
