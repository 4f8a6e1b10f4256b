// Frame backends by name, for the apps' --backend flag: the library never looks a backend
// up by string; the apps do it here, once.
#pragma once

#include <memory>
#include <string>

#include "visimp/render/renderer.h"

namespace visimp::app {

/// "raster" or "osmesa"; throws UsageError for anything else.
std::unique_ptr<Renderer> make_renderer(const std::string& backend, const RenderOptions& options);

}  // namespace visimp::app
