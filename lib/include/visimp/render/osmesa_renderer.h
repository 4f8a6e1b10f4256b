// The OSMesa frame backend: Mesa's off-screen GL on the CPU (llvmpipe), no display and no
// GPU needed. A reference for the built-in rasterizer, and the route to a GPU later: the
// same GL 4.5 core code runs on any driver.
//
// Setup (the fastest measured on llvmpipe): one GL 4.5 core context per worker thread, an
// FBO with a GL_R32UI colour buffer (face ID + 1) and a DEPTH_COMPONENT32F depth buffer,
// IDs as a flat integer vertex attribute over unshared vertices (faster than
// gl_PrimitiveID). A program may also raise glibc's trim threshold
// (keep_allocator_memory_for_osmesa) so llvmpipe's large per-frame allocations are not
// returned to the kernel and faulted back in every frame; the library never does it itself.
//
// Lives in its own CMake target (visimp_render_osmesa) so nothing else links GL.
#pragma once

#include <memory>

#include "visimp/render/renderer.h"

namespace visimp {

/// Throws BackendError (core/errors.h) if no GL 4.5 core context can be created here.
std::unique_ptr<Renderer> make_osmesa_renderer(const RenderOptions& options);

/// Process-wide and once: glibc keeps freed memory up to 512 MiB instead of trimming it, so
/// llvmpipe's per-frame buffers are reused rather than faulted in again. Opt-in, for programs that own their process
/// (the visimp apps and benchmarks call it); glibc only.
void keep_allocator_memory_for_osmesa();

}  // namespace visimp
