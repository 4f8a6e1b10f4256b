#include "backends.h"
#include "cli.h"

#include <algorithm>

#include "visimp/core/errors.h"
#include "visimp/render/osmesa_renderer.h"

namespace visimp::app {

std::unique_ptr<Renderer> make_renderer(const std::string& backend, const RenderOptions& options) {
  if (backend == "raster") return make_raster_renderer(options);
  if (backend == "osmesa") {
    keep_allocator_memory_for_osmesa();  // the app owns its process
    return make_osmesa_renderer(options);
  }
  throw UsageError("--backend " + backend + ": expected raster or osmesa");
}

std::vector<OptionSpec> describe_options(SamplingOptions& o) {
  return {
      option_spec("--cameras", "SET", o.cameras,
                  "6|18|66|258|1026|4098 (octahedron), k0..k5 (level), dodecahedron, or a file of 'x y z' lines"),
      option_spec("--resolution", "R", o.resolution, "frame width and height in pixels, 16..8192"),
      option_spec("--backend", "NAME", o.backend, "raster (built-in CPU rasterizer) or osmesa (Mesa llvmpipe)"),
      option_spec("--threads", "N", o.threads, "worker threads, 0 = one per hardware thread"),
  };
}

RenderOptions render_options(const SamplingOptions& o) {
  check_pixels(o.resolution, "--resolution");
  if (o.threads > kMaxThreads) throw UsageError("--threads must be at most " + std::to_string(kMaxThreads));
  return {static_cast<int>(o.resolution), static_cast<unsigned>(o.threads)};
}

}  // namespace visimp::app
