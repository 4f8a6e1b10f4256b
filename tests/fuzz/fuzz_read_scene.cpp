// libFuzzer target for the scene formats read through assimp (glTF, GLB, 3MF, COLLADA, FBX,
// X3D). The content picks the format, as it does for stdin (3MF, a zip, when nothing else
// matches). As for our own readers: invalid input must end in IoError or InvalidMeshError, and
// a mesh that is accepted must be sound. assimp itself is Debian's build, not instrumented:
// coverage guides the fuzzer only through our code, and ASan sees assimp's faults only where
// they reach our code or crash; docs/formats.md says so.
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string_view>

#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"
#include "visimp/io/scene_formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace visimp;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
#ifdef VISIMP_FUZZ_FORMAT
  const Format format = Format::VISIMP_FUZZ_FORMAT;
#else
  const std::optional<Format> detected = detect_format(bytes);
  const Format format = detected && is_scene_format(*detected) ? *detected : Format::threemf;
#endif
  try {
    FaceGroups groups;
    const Mesh mesh = read_mesh_from_bytes(bytes, format, "fuzz-input", &groups);
    if (groups.face_group.size() != mesh.num_faces()) std::abort();
    for (const std::uint32_t g : groups.face_group)
      if (g >= groups.names.size()) std::abort();
    for (const Face& f : mesh.faces)
      for (VertexIndex v : f)
        if (v >= mesh.num_vertices()) std::abort();
    for (const Vec3& p : mesh.positions)
      if (!is_finite(p)) std::abort();
  } catch (const IoError&) {
  } catch (const InvalidMeshError&) {
  }
  return 0;
}
