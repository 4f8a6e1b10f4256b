// bench_field: the visibility field's costs against its alternatives, side by side in one run
// (docs/field.md): `field build` with the defaults (goal ≤ 60 s on the dragon, 2 cores), and
// per viewpoint at 480² with subsample 4 (goal ≤ 5 ms): resampling the field, against
// visibility tracing (Embree rays through the same pixels) and the full perspective render.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench_main.h"
#include "visimp/field/field.h"
#include "visimp/field/resample.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/perspective.h"
#include "visimp/render/ray_caster.h"

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

struct Stats {
  double min = 0, median = 0, max = 0;
};
Stats stats(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return {v.front(), v[v.size() / 2], v.back()};
}

constexpr const char* kUsage =
    "usage: bench_field [MESH...]\n"
    "Builds the visibility field of each mesh (default: ../shared/meshes dragon and ifc_house_messy) with\n"
    "the defaults and times, over 16 viewpoints around it at 480² with subsample 4: resampling the field,\n"
    "visibility tracing through the same pixels (Embree) and the full perspective render (one thread).\n";

}  // namespace

int main(int argc, char** argv) {
  return bench::guarded_main("bench_field", kUsage, argc, argv, [](const std::vector<std::string>& args) {
    using namespace visimp;
    const std::vector<std::string> meshes =
        args.empty() ? bench::default_meshes("bench_field", {{"dragon.ply", "bunny.ply"}, {"ifc_house_messy.ply", ""}})
                     : args;
    std::printf("%-22s %9s %7s %9s %9s | %-24s %-24s %-24s | %8s %8s\n", "mesh", "faces", "cells", "build s",
                "Mrays/s", "resample ms min/med/max", "tracing ms min/med/max", "full render ms", "trace/rs",
                "full/rs");
    for (const std::string& path : meshes) {
      const Mesh mesh = read_mesh(path);
      const VisibilityField field = build_field(mesh, FieldOptions{});
      const FieldResampler resampler(field);
      const Vec3 c = field.box.center();
      std::vector<std::array<float, 3>> relative(mesh.num_vertices());
      for (std::size_t i = 0; i < relative.size(); ++i) {
        const Vec3 p = mesh.positions[i] - c;
        relative[i] = {float(p.x), float(p.y), float(p.z)};
      }
      const RayCaster caster(relative, mesh.faces);
      PerspectiveRasterizer raster;
      PerspectiveFrame frame;
      std::vector<double> resample_ms, trace_ms, full_ms;
      ResampleOptions options;  // subsample 4, no post-filter: the query defaults
      ResampleResult result;
      const double radius = 0.8 * field.box.diagonal();
      for (int k = 0; k < 16; ++k) {
        const double a = 2 * M_PI * k / 16;
        const Vec3 eye = c + Vec3{std::cos(a), 0.35, std::sin(a)} * radius;
        const PerspectiveView view = PerspectiveView::looking_at(eye, c, 60, 480, 1e-3 * field.box.diagonal());
        for (int repeat = 0; repeat < 3; ++repeat) {
          auto t = Clock::now();
          resampler.resample(view, options, result);
          resample_ms.push_back(ms_since(t));
          t = Clock::now();
          std::size_t hits = 0;
          const std::array<float, 3> origin{float(eye.x - c.x), float(eye.y - c.y), float(eye.z - c.z)};
          for (int j = 0; j < 240; ++j) {
            for (int i = 0; i < 240; ++i) {
              const Vec3 d = view.pixel_ray(2 * i + 0.5, 2 * j + 0.5);
              hits += caster.first_hit(origin, {float(d.x), float(d.y), float(d.z)}) != RayCaster::kNoHit;
            }
          }
          trace_ms.push_back(ms_since(t));
          if (hits == 0 && result.cells_marked > 0) std::fprintf(stderr, "bench_field: note: a view saw nothing\n");
        }
        PerspectiveView local = view;
        local.eye = eye - c;
        const auto t = Clock::now();
        raster.draw(relative, mesh.faces, nullptr, local, frame);
        full_ms.push_back(ms_since(t));
      }
      const Stats r = stats(resample_ms), tr = stats(trace_ms), f = stats(full_ms);
      const std::string name = std::filesystem::path(path).filename().string();
      std::printf("%-22s %9zu %7zu %9.2f %9.1f | %6.2f %7.2f %7.2f   %6.2f %7.2f %7.2f   %6.1f %7.1f %7.1f  | %8.1f %8.1f\n",
                  name.c_str(), mesh.num_faces(), field.cells.num_cells(), field.seconds_build,
                  static_cast<double>(field.rays) / field.seconds_build / 1e6, r.min, r.median, r.max, tr.min,
                  tr.median, tr.max, f.min, f.median, f.max, tr.median / r.median, f.median / r.median);
    }
    std::printf("(build: 2 cores when available; per view: one thread; ratios of medians)\n");
    return 0;
  });
}
