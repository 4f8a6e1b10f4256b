#include "backends.h"

#include "visimp/core/errors.h"
#include "visimp/render/osmesa_renderer.h"

namespace visimp::app {

std::unique_ptr<Renderer> make_renderer(const std::string& backend, const RenderOptions& options) {
  if (backend == "raster") return make_raster_renderer(options);
  if (backend == "osmesa") return make_osmesa_renderer(options);
  throw UsageError("--backend " + backend + ": expected raster or osmesa");
}

}  // namespace visimp::app
