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
  double weight;  // area represented; 0 for vertex samples (they only count towards the max)
};

std::vector<Sample> sample_surface(const Mesh& m, std::size_t count, std::uint64_t seed) {
  std::vector<Sample> samples;
  std::vector<char> used(m.num_vertices(), 0);
  for (const Face& f : m.faces)
    for (VertexIndex v : f) used[v] = 1;
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (used[v]) samples.push_back({m.positions[v], 0.0});
  double total = 0;
  std::vector<double> area(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    area[f] = is_degenerate(m, m.faces[f]) ? 0.0 : 0.5 * norm(face_normal_unnormalized(m, m.faces[f]));
    total += area[f];
  }
  if (!(total > 0)) return samples;
  Random rng(seed);
  samples.reserve(samples.size() + count + m.num_faces());
  // Each face gets floor(count·share + u) samples (expected count·share), each carrying an
  // equal part of the face's area, so sums over samples estimate integrals over the surface.
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    if (area[f] == 0) continue;
    const std::size_t n = static_cast<std::size_t>(std::floor(double(count) * area[f] / total + rng.uniform()));
    const Vec3 &a = m.positions[m.faces[f][0]], &b = m.positions[m.faces[f][1]], &c = m.positions[m.faces[f][2]];
    for (std::size_t i = 0; i < n; ++i) {
      const double r1 = std::sqrt(rng.uniform()), r2 = rng.uniform();
      samples.push_back({a * (1 - r1) + b * (r1 * (1 - r2)) + c * (r1 * r2), area[f] / double(n)});
    }
  }
  return samples;
}

DirectedDistance directed(const std::vector<Sample>& samples, const Mesh& target, int threads,
                          double& weighted_sq_sum, double& weight_sum) {
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

  std::vector<double> distance(samples.size());
  const unsigned workers = threads > 0 ? unsigned(threads) : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < workers; ++t) {
    pool.emplace_back([&, t] {
      for (std::size_t i = t; i < samples.size(); i += workers) {
        const Vec3& p = samples[i].p;
        distance[i] = std::sqrt(tree.squared_distance(Point(p.x, p.y, p.z)));
      }
    });
  }
  for (auto& th : pool) th.join();

  DirectedDistance d;
  double sum = 0, sq = 0, w = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {  // serial: same rounding for any thread count
    d.max = std::max(d.max, distance[i]);
    sum += samples[i].weight * distance[i];
    sq += samples[i].weight * distance[i] * distance[i];
    w += samples[i].weight;
  }
  d.samples = samples.size();
  d.mean = w > 0 ? sum / w : 0;
  d.rms = w > 0 ? std::sqrt(sq / w) : 0;
  weighted_sq_sum += sq;
  weight_sum += w;
  return d;
}

}  // namespace

SurfaceDistance surface_distance(const Mesh& a, const Mesh& b, const SurfaceDistanceOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t count = options.samples ? options.samples : 10 * std::max(a.num_faces(), b.num_faces());
  SurfaceDistance r;
  double sq = 0, w = 0;
  r.a_to_b = directed(sample_surface(a, count, options.seed), b, options.threads, sq, w);
  r.b_to_a = directed(sample_surface(b, count, options.seed + 1), a, options.threads, sq, w);
  r.hausdorff = std::max(r.a_to_b.max, r.b_to_a.max);
  r.rms = w > 0 ? std::sqrt(sq / w) : 0;
  r.diagonal = bounding_box(a).diagonal();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace visimp
