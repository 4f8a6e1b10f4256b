#include "visimp/metrics/surface_distance.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"

namespace visimp {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// splitmix64: a tiny, portable generator so samples are identical on every platform.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }

 private:
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  std::uint64_t state_;
};

struct Sample {
  Vec3 p;
  double weight;       // area represented; 0 for vertex and edge samples (they only count towards the max)
  std::int64_t owner;  // face index for face samples, -(vertex + 1) for vertex samples, 0 for edge samples
};

std::vector<Sample> sample_surface(const Mesh& m, std::size_t count, std::size_t edge_count, std::uint64_t seed,
                                   FaceSampling sampling) {
  std::vector<Sample> samples;
  std::vector<char> used(m.num_vertices(), 0);
  for (const Face& f : m.faces)
    for (VertexIndex v : f) used[v] = 1;
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (used[v]) samples.push_back({m.positions[v], 0.0, -static_cast<std::int64_t>(v) - 1});
  double total = 0;
  std::vector<double> area(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    area[f] = is_degenerate(m, m.faces[f]) ? 0.0 : 0.5 * norm(face_normal_unnormalized(m, m.faces[f]));
    total += area[f];
  }
  if (!(total > 0)) return samples;
  Random rng(seed);
  // Edge samples (for the maximum): each distinct edge gets floor(edge_count·share + u) points
  // spread along it, share by length.
  std::vector<std::uint64_t> edges;
  edges.reserve(m.num_faces() * 3);
  for (const Face& f : m.faces)
    for (int k = 0; k < 3; ++k) {
      const VertexIndex a = f[k], b = f[(k + 1) % 3];
      if (a != b) edges.push_back((std::uint64_t{std::min(a, b)} << 32) | std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  double total_length = 0;
  for (std::uint64_t e : edges) total_length += norm(m.positions[e >> 32] - m.positions[e & 0xffffffffu]);
  if (total_length > 0) {
    for (std::uint64_t e : edges) {
      const Vec3 &a = m.positions[e >> 32], &b = m.positions[e & 0xffffffffu];
      const std::size_t n =
          static_cast<std::size_t>(std::floor(double(edge_count) * norm(b - a) / total_length + rng.uniform()));
      for (std::size_t i = 0; i < n; ++i) {
        const double t = (double(i) + rng.uniform()) / double(n);
        samples.push_back({a * (1 - t) + b * t, 0.0, 0});
      }
    }
  }
  samples.reserve(samples.size() + count + m.num_faces());
  // Each face gets floor(count·share + u) samples (expected count·share), each carrying an
  // equal part of the face's area, so sums over samples estimate integrals over the surface.
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    if (area[f] == 0) continue;
    const std::size_t n = static_cast<std::size_t>(std::floor(double(count) * area[f] / total + rng.uniform()));
    if (n == 0) continue;
    const Vec3 &a = m.positions[m.faces[f][0]], &b = m.positions[m.faces[f][1]], &c = m.positions[m.faces[f][2]];
    const auto owner = static_cast<std::int64_t>(f);
    if (sampling == FaceSampling::random) {
      for (std::size_t i = 0; i < n; ++i) {
        const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
        samples.push_back({a * (1 - r1) + b * (r1 * (1 - r2)) + c * (r1 * r2), area[f] / double(n), owner});
      }
      continue;
    }
    // Stratified: split the face into k² congruent cells (k = √n rounded) and put one
    // uniform point in each. In barycentric units of 1/k, cell (i, j) is the upright
    // triangle S ∈ [i, i+1], T ∈ [j, j+1], S + T ≤ i + j + 1, or its inverted neighbour.
    const std::size_t k = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(std::sqrt(double(n)))));
    const double weight = area[f] / double(k * k), kk = double(k);
    auto emit = [&](double S, double T) { samples.push_back({a * (1 - (S + T) / kk) + b * (S / kk) + c * (T / kk), weight, owner}); };
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
  return samples;
}

// Exact distance of every sample to `target`, in parallel (each distance is independent).
std::vector<double> distances(const std::vector<Sample>& samples, const Mesh& target, int threads,
                              double& seconds_index, double& seconds_queries) {
  auto t = std::chrono::steady_clock::now();
  std::vector<Triangle> triangles;
  triangles.reserve(target.num_faces());
  for (const Face& f : target.faces) {
    if (is_degenerate(target, f)) continue;
    const Vec3 &a = target.positions[f[0]], &b = target.positions[f[1]], &c = target.positions[f[2]];
    triangles.emplace_back(Point(a.x, a.y, a.z), Point(b.x, b.y, b.z), Point(c.x, c.y, c.z));
  }
  if (triangles.empty()) throw InvalidMeshError("surface distance: a mesh has no non-degenerate face");
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  seconds_index += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();

  t = std::chrono::steady_clock::now();
  std::vector<double> distance(samples.size());
  const unsigned workers = threads > 0 ? unsigned(threads) : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned w = 0; w < workers; ++w) {
    pool.emplace_back([&, w] {
      for (std::size_t i = w; i < samples.size(); i += workers) {
        const Vec3& p = samples[i].p;
        distance[i] = std::sqrt(tree.squared_distance(Point(p.x, p.y, p.z)));
      }
    });
  }
  for (auto& th : pool) th.join();
  seconds_queries += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  return distance;
}

DirectedDistance summarize(const std::vector<Sample>& samples, const std::vector<double>& distance,
                           std::size_t bins, double& weighted_sq_sum, double& weight_sum) {
  DirectedDistance d;
  double sum = 0, sq = 0, w = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {  // serial: same rounding for any thread count
    d.max = std::max(d.max, distance[i]);
    sum += samples[i].weight * distance[i];
    sq += samples[i].weight * distance[i] * distance[i];
    w += samples[i].weight;
    d.face_samples += samples[i].weight > 0 ? 1 : 0;
  }
  d.samples = samples.size();
  d.area = w;
  d.mean = w > 0 ? sum / w : 0;
  d.rms = w > 0 ? std::sqrt(sq / w) : 0;
  d.histogram.assign(std::max<std::size_t>(bins, 1), 0.0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].weight == 0 || w == 0) continue;
    const double x = d.max > 0 ? distance[i] / d.max : 0.0;
    const std::size_t bin = std::min(d.histogram.size() - 1, static_cast<std::size_t>(x * double(d.histogram.size())));
    d.histogram[bin] += samples[i].weight / w;
  }
  weighted_sq_sum += sq;
  weight_sum += w;
  return d;
}

VisibleDistance summarize_visible(const std::vector<Sample>& samples, const std::vector<double>& distance,
                                  const std::vector<float>& face_visibility) {
  VisibleDistance v;
  double sum = 0, sq = 0, w = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (samples[i].weight == 0) continue;
    const double visibility = face_visibility[static_cast<std::size_t>(samples[i].owner)];
    if (visibility > 0) v.max = std::max(v.max, distance[i]);
    const double weight = samples[i].weight * visibility;
    sum += weight * distance[i];
    sq += weight * distance[i] * distance[i];
    w += weight;
  }
  v.visible_area = w;
  v.mean = w > 0 ? sum / w : 0;
  v.rms = w > 0 ? std::sqrt(sq / w) : 0;
  return v;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (options.visibility_weighted && a.face_quality.size() != a.num_faces()) {
    throw InvalidMeshError("visibility-weighted distance needs V of every face of A as face quality");
  }
  std::size_t count = options.samples ? options.samples : 10 * std::max(a.num_faces(), b.num_faces());
  if (options.density > 0) {
    const MeshStats sa = analyze(a), sb = analyze(b);
    count = static_cast<std::size_t>(std::ceil(options.density * std::max(sa.area, sb.area)));
  }
  const std::size_t edges = options.edge_samples ? options.edge_samples : std::max(a.num_faces(), b.num_faces());
  SurfaceDistance r;
  auto t = std::chrono::steady_clock::now();
  const std::vector<Sample> on_a = sample_surface(a, count, edges, options.seed, options.sampling);
  const std::vector<Sample> on_b = sample_surface(b, count, edges, options.seed + 1, options.sampling);
  r.seconds_sampling = seconds_since(t);
  const std::vector<double> from_a = distances(on_a, b, options.threads, r.seconds_index, r.seconds_queries);
  const std::vector<double> from_b = distances(on_b, a, options.threads, r.seconds_index, r.seconds_queries);
  double sq = 0, w = 0;
  r.a_to_b = summarize(on_a, from_a, options.histogram_bins, sq, w);
  r.b_to_a = summarize(on_b, from_b, options.histogram_bins, sq, w);
  r.hausdorff = std::max(r.a_to_b.max, r.b_to_a.max);
  r.rms = w > 0 ? std::sqrt(sq / w) : 0;
  r.diagonal = bounding_box(a).diagonal();
  if (options.visibility_weighted) r.visible = summarize_visible(on_a, from_a, a.face_quality);
  if (options.vertex_errors) {
    r.vertex_error.assign(a.num_vertices(), 0.0f);
    r.face_error.assign(a.num_faces(), 0.0f);
    for (std::size_t i = 0; i < on_a.size(); ++i) {
      if (on_a[i].owner < 0) {
        r.vertex_error[static_cast<std::size_t>(-on_a[i].owner - 1)] = static_cast<float>(from_a[i]);
      } else if (on_a[i].weight > 0) {
        float& e = r.face_error[static_cast<std::size_t>(on_a[i].owner)];
        e = std::max(e, static_cast<float>(from_a[i]));
      }
    }
  }
  r.seconds = seconds_since(start);
  return r;
}

}  // namespace visimp
