// Visibility benchmark: both frame backends side by side on the same meshes, 258 cameras at
// 480², in one run, plus the "floor": the least work any rasterizer must do (project every
// vertex and read every face once per camera). Each backend runs in a forked child
// (child_process.h) for its own CPU time and peak memory.
//
// usage: bench_visibility [MESH.ply ...]   (default: dragon, bunny)
//        bench_visibility --reference [MESH.ply ...]
//          visimp at its defaults (258 cameras, 480²) against the Embree ray-cast reference
//          (tests/reference: 1026 cameras, 1024², faces refined to ≤ 0.8% of the bounding-sphere
//          diameter) and against itself at 1026 cameras and 1024² (default: the CAD parts and the
//          bunny with the reference, the dragon without: ~10 minutes on 2 cores).
#include <atomic>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "bench_main.h"
#include "child_process.h"
#include "raycast_visibility.h"
#include "visimp/core/bounding_box.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/osmesa_renderer.h"
#include "visimp/visibility/visibility.h"

namespace {

using visimp::Mesh;

// Paper values (Zhang & Turk 2002, Table 1), for the docs' comparison.
double paper_visibility(const std::string& name) {
  if (name.find("dragon") != std::string::npos) return 0.804;
  if (name.find("bunny") != std::string::npos) return 0.958;
  return -1;
}

// A consumer that does nothing: what rendering alone costs.
struct Discard final : visimp::FrameConsumer {
  void begin(unsigned) override {}
  void consume(const visimp::Frame&, std::size_t, unsigned) override {}
};

// The floor: per camera, project the vertices and touch every face's three vertices.
std::vector<double> floor_pass(const Mesh& input, const visimp::CameraSet& cameras, int resolution) {
  // The same faces the backends render: after refinement.
  const visimp::BoundingBox box = visimp::bounding_box(input);
  const auto refined = visimp::refine_long_edges(
      input, visimp::refinement_edge_length(visimp::view_radius(box), resolution, 0.25), 30000000);
  const Mesh& mesh = refined ? refined->mesh : input;
  const visimp::RenderScene scene = visimp::RenderScene::from_mesh(mesh, false);
  const unsigned workers = visimp::worker_count(0, cameras.size());
  std::vector<std::vector<visimp::ScreenVertex>> screen(workers);
  std::atomic<std::uint64_t> sink{0};
  const double w0 = bench::wall_seconds();
  visimp::for_each_camera(0, cameras.size(), workers, nullptr, [&](unsigned w, std::size_t c) {
    const auto view = visimp::OrthoView::looking_from(cameras.directions[c], scene.radius, resolution);
    visimp::project_vertices(scene, view, screen[w]);
    std::uint64_t covered = 0;
    for (const visimp::Face& f : scene.faces) {
      const float x = std::min({screen[w][f[0]].x, screen[w][f[1]].x, screen[w][f[2]].x});
      covered += x > 0.5f * static_cast<float>(resolution) ? 1 : 0;
    }
    sink += covered;
  });
  return {bench::wall_seconds() - w0, static_cast<double>(mesh.num_faces())};
}

visimp::Visibility visimp_visibility(const Mesh& mesh, const visimp::CameraSet& cameras, int resolution) {
  auto renderer = visimp::make_raster_renderer({resolution, 0});
  return visimp::compute_visibility(mesh, cameras, *renderer);
}

// visimp against the ray-cast reference and against itself at the reference's sampling.
int reference_table(std::vector<std::string> meshes) {
  if (meshes.empty()) {
    meshes = bench::default_meshes("bench_visibility", {{"kicad_cap_snapin_d40.ply", ""},
                                                        {"kicad_esp_wroom02.ply", "kicad_esp_wroom02.ply"},
                                                        {"kicad_dsub62_male.ply", ""},
                                                        {"bunny.ply", "bunny.ply"},
                                                        {"dragon.ply", ""}});
  }
  const visimp::CameraSet cameras = visimp::octahedron_cameras(3), fine = visimp::octahedron_cameras(4);
  std::printf(
      "| mesh | V(M) visimp 258×480² | hidden | s | V(M) visimp 1026×1024² | s | V(M) ray cast 1026×1024² | "
      "hidden | s | mean abs dV | dV(M) | ray-cast hidden area at V <= 0.02 | s visimp / ray cast |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& path : meshes) {
    const Mesh mesh = visimp::read_mesh(path);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    const visimp::Visibility v = visimp_visibility(mesh, cameras, 480);
    const visimp::Visibility v_fine = visimp_visibility(mesh, fine, 1024);
    std::printf("| %s | %.4f | %.2f%% | %.2f | %.4f | %.2f |", name.c_str(), v.mesh, 100 * v.stats.hidden_area_fraction,
                v.stats.seconds_total, v_fine.mesh, v_fine.stats.seconds_total);
    if (name.find("dragon") != std::string::npos) {  // ~10 minutes of rays: the self-check only
      std::printf(" | | | | | %+.4f (vs 1026×1024²) | | |\n", v.mesh - v_fine.mesh);
      std::fflush(stdout);
      continue;
    }
    const visimp::reference::RaycastVisibility ref = visimp::reference::raycast_visibility(mesh, fine);
    const visimp::reference::VisibilityAgreement a = visimp::reference::compare_visibility(mesh, v.face, ref);
    std::printf(" %.4f | %.2f%% | %.1f | %.4f | %+.4f | %.2f%% | %.3f |\n", ref.mesh, 100 * ref.hidden_area_fraction,
                ref.seconds, a.mean_abs_difference, a.mesh_difference, 100 * a.hidden_area_low,
                v.stats.seconds_total / ref.seconds);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

constexpr const char* kUsage =
    "usage: bench_visibility [MESH ...]              both backends and the floor (default: dragon, bunny)\n"
    "       bench_visibility --reference [MESH ...]  against the Embree ray caster (~10 minutes)\n"
    "       bench_visibility --raster [MESH ...]     the floor and the software rasteriser only (quick A/B runs)\n"
    "       --repeat N: render+tally is the fastest of N runs (default 1)\n"
    "Without ../shared/meshes the bundled meshes stand in (a note on stderr says which).\n";

int run(const std::vector<std::string>& args) {
  std::vector<std::string> meshes;
  bool reference = false, raster_only = false;
  int repeat = 1;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--repeat") {
      const std::string value = i + 1 < args.size() ? args[++i] : "nothing";
      const bool digits = !value.empty() && value.size() <= 3 && value.find_first_not_of("0123456789") == std::string::npos;
      repeat = digits ? std::stoi(value) : 0;
      if (repeat < 1 || repeat > 100) throw visimp::UsageError("--repeat wants 1..100, got " + value);
    } else if (a == "--reference")
      reference = true;
    else if (a == "--raster")
      raster_only = true;
    else if (!a.empty() && a[0] == '-')
      throw visimp::UsageError("unknown option " + a + " (see --help)");
    else
      meshes.push_back(a);
  }
  if (reference) return reference_table(meshes);
  if (meshes.empty())
    meshes = bench::default_meshes("bench_visibility", {{"dragon.ply", "bunny.ply"}, {"bunny.ply", "bunny.ply"}});
  const visimp::CameraSet cameras = visimp::octahedron_cameras(3);
  const int resolution = 480;
  std::printf(
      "| mesh | faces | faces rendered | method | prepare s | render+tally s (wall) | render only s (wall) | "
      "CPU s | peak MB | V(M) | paper V(M) | render vs floor | vs raster |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& path : meshes) {
    const Mesh mesh = visimp::read_mesh(path);
    const std::string name = path.substr(path.find_last_of('/') + 1);
    const bench::ChildResult floor = bench::run_in_child(2, [&] { return floor_pass(mesh, cameras, resolution); });
    std::printf("| %s | %zu | %.0f | floor | | %.3f | | %.3f | %.1f | | | 1.00 | |\n", name.c_str(), mesh.num_faces(),
                floor.values[1], floor.values[0], floor.cpu, floor.peak_mb);
    double raster_render = 0;
    for (const char* backend : {"raster", "osmesa"}) {
      if (raster_only && std::string(backend) != "raster") continue;
      const bench::ChildResult r = bench::run_in_child(6, [&] {
        const visimp::RenderOptions options{resolution, 0};
        auto renderer = std::string(backend) == "raster"
                            ? visimp::make_raster_renderer(options)
                            : (visimp::keep_allocator_memory_for_osmesa(), visimp::make_osmesa_renderer(options));
        double t = bench::wall_seconds();
        const visimp::VisibilityJob job(mesh, resolution, {});
        const double prepare = bench::wall_seconds() - t;
        // The fastest of `repeat` runs: on a shared machine one run's wall time drifts by ±15%.
        double render = std::numeric_limits<double>::infinity();
        visimp::VisibilityTally tally;
        for (int r = 0; r < repeat; ++r) {
          t = bench::wall_seconds();
          tally = job.render(cameras, 0, cameras.size(), *renderer);
          render = std::min(render, bench::wall_seconds() - t);
        }
        const visimp::Visibility v = job.finish(tally);
        // Rendering alone, for the split between the backend and the tally.
        Discard discard;
        t = bench::wall_seconds();
        renderer->render(job.scene(), cameras, 0, cameras.size(), discard);
        const double render_only = bench::wall_seconds() - t;
        return std::vector<double>{prepare, render, render_only, v.mesh, double(job.stats().refined_faces), 0};
      });
      if (!r.ok) {
        std::printf("| %s | %zu | | %s | failed | | | | | | | | |\n", name.c_str(), mesh.num_faces(), backend);
        continue;
      }
      if (std::string(backend) == "raster") raster_render = r.values[1];
      const double paper = paper_visibility(name);
      std::printf("| %s | %zu | %.0f | %s | %.3f | %.3f | %.3f | %.2f | %.1f | %.3f | %s | %.2f | %.2f |\n",
                  name.c_str(), mesh.num_faces(), r.values[4], backend, r.values[0], r.values[1], r.values[2], r.cpu,
                  r.peak_mb, r.values[3], paper > 0 ? std::to_string(paper).substr(0, 5).c_str() : "",
                  r.values[1] / floor.values[0], r.values[1] / raster_render);
      std::fflush(stdout);
    }
  }
  return 0;
}

int main(int argc, char** argv) { return bench::guarded_main("bench_visibility", kUsage, argc, argv, run); }
