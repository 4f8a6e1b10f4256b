// Frame backends by name, for the apps' --backend flag: the library never looks a backend
// up by string; the apps do it here, once.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/option_table.h"
#include "visimp/render/renderer.h"

namespace visimp::app {

/// "raster" or "osmesa"; throws UsageError for anything else.
std::unique_ptr<Renderer> make_renderer(const std::string& backend, const RenderOptions& options);

/// How the camera sphere is sampled: the flags every command that renders visibility shares.
struct SamplingOptions {
  std::string cameras = kDefaultCameraSet;
  std::size_t resolution = static_cast<std::size_t>(RenderOptions{}.resolution);
  std::string backend = "raster";
  std::size_t threads = RenderOptions{}.threads;
};
std::vector<OptionSpec> describe_options(SamplingOptions& o);
RenderOptions render_options(const SamplingOptions& o);

}  // namespace visimp::app
