// libFuzzer target for one mesh reader (VISIMP_FUZZ_FORMAT picks it). Invalid input must
// end in IoError or InvalidMeshError; anything else (a crash, a sanitizer report, another
// exception, a hang, runaway memory) is a finding. A mesh that is accepted must be sound.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace visimp;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const Mesh mesh = read_mesh_from_bytes(bytes, Format::VISIMP_FUZZ_FORMAT, "fuzz-input");
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
