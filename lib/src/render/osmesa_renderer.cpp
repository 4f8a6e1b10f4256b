// OSMesa backend (see osmesa_renderer.h). Image conventions are those of frame.h: the
// vertex shader computes the same projection as project_vertices(), GL's window
// transform maps NDC x,y to pixels with centres at i + 0.5, and GL_LESS keeps the first
// of equal depths like the raster backend.
//
// libOSMesa is opened at the backend's first use, not linked (core/shared_library.h: Mesa's
// LLVM cost every visimp process ~70 ms of start-up). The headers still give the prototypes
// (for the pointers' types) and the constants; nothing links libOSMesa, so a call that
// bypasses the table below is an undefined symbol (the apps and tests fail to link; test
// App.OnlyTheOsmesaBackendLoadsMesa would see a shared object pull it in).
#define GL_GLEXT_PROTOTYPES 1
#include "visimp/render/osmesa_renderer.h"

#include <GL/osmesa.h>
#include <GL/glcorearb.h>
#include <malloc.h>

#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "../core/shared_library.h"
#include "visimp/core/errors.h"

#ifndef VISIMP_OSMESA_LIBRARY
#define VISIMP_OSMESA_LIBRARY "libOSMesa.so.8"  // the soname since Mesa 7; CMake sets the found one
#endif

namespace visimp {
namespace {

// Every GL entry point the backend calls, by its name without "gl".
#define VISIMP_GL_FUNCTIONS(X) \
  X(AttachShader)              \
  X(BindBuffer)                \
  X(BindFramebuffer)           \
  X(BindRenderbuffer)          \
  X(BindVertexArray)           \
  X(BufferData)                \
  X(CheckFramebufferStatus)    \
  X(ClearBufferfv)             \
  X(ClearBufferuiv)            \
  X(CompileShader)             \
  X(CreateProgram)             \
  X(CreateShader)              \
  X(CullFace)                  \
  X(DepthFunc)                 \
  X(Disable)                   \
  X(DrawArrays)                \
  X(Enable)                    \
  X(EnableVertexAttribArray)   \
  X(FramebufferRenderbuffer)   \
  X(FrontFace)                 \
  X(GenBuffers)                \
  X(GenFramebuffers)           \
  X(GenRenderbuffers)          \
  X(GenVertexArrays)           \
  X(GetError)                  \
  X(GetProgramiv)              \
  X(GetShaderInfoLog)          \
  X(GetShaderiv)               \
  X(GetUniformLocation)        \
  X(LinkProgram)               \
  X(PixelStorei)               \
  X(ReadPixels)                \
  X(RenderbufferStorage)       \
  X(ShaderSource)              \
  X(Uniform1f)                 \
  X(Uniform3f)                 \
  X(UseProgram)                \
  X(VertexAttribIPointer)      \
  X(VertexAttribPointer)       \
  X(Viewport)

// libOSMesa's entry points, resolved once per process.
struct OsmesaApi {
  decltype(&::OSMesaCreateContextAttribs) CreateContextAttribs = nullptr;
  decltype(&::OSMesaDestroyContext) DestroyContext = nullptr;
  decltype(&::OSMesaMakeCurrent) MakeCurrent = nullptr;
#define VISIMP_GL_MEMBER(name) decltype(&::gl##name) name = nullptr;
  VISIMP_GL_FUNCTIONS(VISIMP_GL_MEMBER)
#undef VISIMP_GL_MEMBER
};

OsmesaApi load_osmesa() {
  try {
    const detail::SharedLibrary library(VISIMP_OSMESA_LIBRARY, "libosmesa6");
    OsmesaApi api;
    library.resolve("OSMesaCreateContextAttribs", api.CreateContextAttribs);
    library.resolve("OSMesaDestroyContext", api.DestroyContext);
    library.resolve("OSMesaMakeCurrent", api.MakeCurrent);
#define VISIMP_GL_RESOLVE(name) library.resolve("gl" #name, api.name);
    VISIMP_GL_FUNCTIONS(VISIMP_GL_RESOLVE)
#undef VISIMP_GL_RESOLVE
    return api;
  } catch (const BackendError& e) {
    throw BackendError(std::string("osmesa: ") + e.what() + "; the raster backend needs no GL");
  }
}

// Loads on the first call; a failed load throws and is tried again on the next call.
const OsmesaApi& osmesa() {
  static const OsmesaApi api = load_osmesa();
  return api;
}

constexpr const char* kVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in uint face_id;
uniform vec3 right;
uniform vec3 up;
uniform vec3 direction;
uniform float inv_radius;
flat out uint id;
void main() {
  // x, y as in frame.h; z = 2 depth - 1 with depth = (1 - p.direction / radius) / 2.
  gl_Position = vec4(dot(position, right) * inv_radius, dot(position, up) * inv_radius,
                     -dot(position, direction) * inv_radius, 1.0);
  id = face_id;
}
)";

constexpr const char* kFragmentShader = R"(#version 450 core
flat in uint id;
layout(location = 0) out uint face;
void main() { face = id; }
)";

constexpr const char* kNoContext =
    "osmesa: cannot create an OpenGL 4.5 core context (Mesa's llvmpipe needed; the raster backend needs no GL)";
constexpr int kContextAttributes[] = {OSMESA_FORMAT,
                                      OSMESA_RGBA,
                                      OSMESA_DEPTH_BITS,
                                      0,
                                      OSMESA_PROFILE,
                                      OSMESA_CORE_PROFILE,
                                      OSMESA_CONTEXT_MAJOR_VERSION,
                                      4,
                                      OSMESA_CONTEXT_MINOR_VERSION,
                                      5,
                                      0};

GLuint compile(GLenum type, const char* source) {
  const OsmesaApi& gl = osmesa();
  const GLuint shader = gl.CreateShader(type);
  gl.ShaderSource(shader, 1, &source, nullptr);
  gl.CompileShader(shader);
  GLint ok = 0;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw BackendError(std::string("osmesa: shader does not compile: ") + log);
  }
  return shader;
}

// One GL context with its framebuffer and the scene's geometry, used by one worker thread.
class GlWorker {
 public:
  GlWorker(const RenderScene& scene, int resolution) : resolution_(resolution), dummy_(4, 0) {
    context_ = gl.CreateContextAttribs(kContextAttributes, nullptr);
    if (context_ == nullptr) throw BackendError(kNoContext);
    make_current();

    const GLuint program = gl.CreateProgram();
    gl.AttachShader(program, compile(GL_VERTEX_SHADER, kVertexShader));
    gl.AttachShader(program, compile(GL_FRAGMENT_SHADER, kFragmentShader));
    gl.LinkProgram(program);
    GLint ok = 0;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) throw BackendError("osmesa: shader program does not link");
    gl.UseProgram(program);
    right_ = gl.GetUniformLocation(program, "right");
    up_ = gl.GetUniformLocation(program, "up");
    direction_ = gl.GetUniformLocation(program, "direction");
    gl.Uniform1f(gl.GetUniformLocation(program, "inv_radius"), static_cast<float>(1.0 / scene.radius));

    GLuint buffers[2];
    gl.GenRenderbuffers(2, buffers);
    GLuint framebuffer;
    gl.GenFramebuffers(1, &framebuffer);
    gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    gl.BindRenderbuffer(GL_RENDERBUFFER, buffers[0]);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_R32UI, resolution, resolution);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
    gl.BindRenderbuffer(GL_RENDERBUFFER, buffers[1]);
    gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, resolution, resolution);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffers[1]);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw std::runtime_error("osmesa: R32UI + DEPTH32F framebuffer is not complete");
    }

    // Unshared vertices: three per face, each carrying its face's ID (flat attribute).
    std::vector<float> positions;
    std::vector<GLuint> ids;
    positions.reserve(scene.faces.size() * 9);
    ids.reserve(scene.faces.size() * 3);
    for (std::size_t f = 0; f < scene.faces.size(); ++f) {
      for (VertexIndex v : scene.faces[f]) {
        positions.insert(positions.end(), scene.positions[v].begin(), scene.positions[v].end());
        ids.push_back(static_cast<GLuint>(f + 1));
      }
    }
    vertex_count_ = static_cast<GLsizei>(ids.size());
    GLuint vao, vbo[2];
    gl.GenVertexArrays(1, &vao);
    gl.BindVertexArray(vao);
    gl.GenBuffers(2, vbo);
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo[0]);
    gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(positions.size() * sizeof(float)), positions.data(),
                  GL_STATIC_DRAW);
    gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(0);
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo[1]);
    gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(ids.size() * sizeof(GLuint)), ids.data(), GL_STATIC_DRAW);
    gl.VertexAttribIPointer(1, 1, GL_UNSIGNED_INT, 0, nullptr);
    gl.EnableVertexAttribArray(1);

    gl.Viewport(0, 0, resolution, resolution);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LESS);
    gl.FrontFace(GL_CCW);
    gl.CullFace(GL_BACK);
    culled_vertex_count_ = static_cast<GLsizei>(3 * scene.culled_faces);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    if (gl.GetError() != GL_NO_ERROR) throw std::runtime_error("osmesa: GL error while setting up");
  }

  ~GlWorker() {
    if (context_ != nullptr) gl.DestroyContext(context_);
  }
  GlWorker(const GlWorker&) = delete;
  GlWorker& operator=(const GlWorker&) = delete;

  void draw(Frame& frame) {
    make_current();
    const OrthoView& v = frame.view;
    gl.Uniform3f(right_, static_cast<float>(v.right.x), static_cast<float>(v.right.y), static_cast<float>(v.right.z));
    gl.Uniform3f(up_, static_cast<float>(v.up.x), static_cast<float>(v.up.y), static_cast<float>(v.up.z));
    gl.Uniform3f(direction_, static_cast<float>(v.direction.x), static_cast<float>(v.direction.y),
                 static_cast<float>(v.direction.z));
    const GLuint zero[4] = {0, 0, 0, 0};
    const GLfloat far = 1.0f;
    gl.ClearBufferuiv(GL_COLOR, 0, zero);
    gl.ClearBufferfv(GL_DEPTH, 0, &far);
    // Faces of closed outward surfaces first, culled; then the ones drawn from both sides.
    if (culled_vertex_count_ > 0) {
      gl.Enable(GL_CULL_FACE);
      gl.DrawArrays(GL_TRIANGLES, 0, culled_vertex_count_);
      gl.Disable(GL_CULL_FACE);
    }
    if (vertex_count_ > culled_vertex_count_) {
      gl.DrawArrays(GL_TRIANGLES, culled_vertex_count_, vertex_count_ - culled_vertex_count_);
    }
    const std::size_t pixels = static_cast<std::size_t>(resolution_) * static_cast<std::size_t>(resolution_);
    frame.ids.resize(pixels);
    frame.depth.resize(pixels);
    gl.ReadPixels(0, 0, resolution_, resolution_, GL_RED_INTEGER, GL_UNSIGNED_INT, frame.ids.data());
    gl.ReadPixels(0, 0, resolution_, resolution_, GL_DEPTH_COMPONENT, GL_FLOAT, frame.depth.data());
    if (gl.GetError() != GL_NO_ERROR) throw std::runtime_error("osmesa: GL error while rendering");
  }

 private:
  void make_current() {
    // The context renders into the FBO; OSMesa still wants a buffer to bind to.
    if (!gl.MakeCurrent(context_, dummy_.data(), GL_UNSIGNED_BYTE, 1, 1)) {
      throw std::runtime_error("osmesa: cannot make the context current");
    }
  }

  const OsmesaApi& gl = osmesa();
  int resolution_;
  std::vector<unsigned char> dummy_;
  OSMesaContext context_ = nullptr;
  GLint right_ = -1, up_ = -1, direction_ = -1;
  GLsizei vertex_count_ = 0;
  GLsizei culled_vertex_count_ = 0;  // the first culled_faces faces of the scene
};

class OsmesaRenderer final : public Renderer {
 public:
  explicit OsmesaRenderer(const RenderOptions& options) : options_(options) {
    check_render_options(options);
    // Fail here, before any work, rather than on the first frame after a long refinement.
    const OsmesaApi& gl = osmesa();
    const OSMesaContext probe = gl.CreateContextAttribs(kContextAttributes, nullptr);
    if (probe == nullptr) throw BackendError(kNoContext);
    gl.DestroyContext(probe);
  }

  std::string name() const override { return "osmesa"; }
  int resolution() const override { return options_.resolution; }

  void render(const RenderScene& scene, const CameraSet& cameras, std::size_t first, std::size_t last,
              FrameConsumer& consumer, RenderObserver* observer) override {
    std::vector<std::unique_ptr<GlWorker>> contexts;
    render_frames(
        scene, cameras, first, last, options_, consumer, observer, [&](unsigned workers) { contexts.resize(workers); },
        [&](unsigned worker, Frame& frame) {
          // Each context is created on, and used by, the one thread of its worker.
          if (!contexts[worker]) contexts[worker] = std::make_unique<GlWorker>(scene, options_.resolution);
          contexts[worker]->draw(frame);
          project_vertices(scene, frame.view, frame.vertices);
        });
  }

 private:
  RenderOptions options_;
};

}  // namespace

std::unique_ptr<Renderer> make_osmesa_renderer(const RenderOptions& options) {
  return std::make_unique<OsmesaRenderer>(options);
}

void keep_allocator_memory_for_osmesa() {
  // llvmpipe allocates and frees large scratch buffers every frame; with glibc's default
  // thresholds they go back to the kernel and are faulted in again each time.
  static std::once_flag tuned;
  std::call_once(tuned, [] {
    mallopt(M_TRIM_THRESHOLD, 512 * 1024 * 1024);
    mallopt(M_MMAP_THRESHOLD, 512 * 1024 * 1024);
  });
}

}  // namespace visimp
