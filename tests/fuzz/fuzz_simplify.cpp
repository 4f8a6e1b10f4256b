// libFuzzer target for read → simplify → write. The first byte picks the format and the
// target ratio, the last byte's low bit --no-folds and its next bit --area-floor 1; the rest is
// the file. Accepted meshes must
// simplify to a valid mesh with finite coordinates that writes without error and has no more
// non-manifold edges, non-manifold vertices or misoriented edges than the input.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string_view>
#include <vector>

#include "visimp/core/errors.h"
#include "visimp/core/face_subset.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/core/validate.h"
#include "visimp/io/mesh_io.h"
#include "visimp/simplify/simplify.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace visimp;
  if (size < 1) return 0;
  const Format formats[] = {Format::ply, Format::obj, Format::off, Format::stl};
  const Format format = formats[data[0] % 4];
  const double ratio = 0.05 + 0.9 * ((data[0] >> 2) / 63.0);
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  Mesh mesh;
  try {
    mesh = read_mesh_from_bytes(bytes, format, "fuzz-input");
  } catch (const IoError&) {
    return 0;
  } catch (const InvalidMeshError&) {
    return 0;
  }
  if (mesh.num_faces() > 20000) return 0;  // keep each run fast
  SimplifyOptions options;
  options.target_ratio = ratio;
  options.prevent_folds = (data[size - 1] & 1) != 0;  // the last byte's low bit: both legality sets
  options.area_floor = (data[size - 1] & 2) != 0 ? 1.0 : 0.0;  // and its next bit: both area weightings
  const Simplified out = simplify(mesh, options);
  if (!validate(out.mesh).ok()) std::abort();
  std::vector<std::uint8_t> proper(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Face& t = mesh.faces[f];
    proper[f] = t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
  }
  // The input's defects counted both ways: with those faces (a run with nothing to do returns
  // the input as it is) and without them (what the collapse engine works on).
  const MeshStats raw = analyze(mesh), cleaned = analyze(keep_faces(mesh, proper)), after = analyze(out.mesh);
  auto more_than_input = [&](std::size_t MeshStats::*count) {
    return after.*count > std::max(raw.*count, cleaned.*count);
  };
  if (more_than_input(&MeshStats::non_manifold_edges) || more_than_input(&MeshStats::non_manifold_vertices) ||
      more_than_input(&MeshStats::misoriented_edges))
    std::abort();
  for (const Vec3& p : out.mesh.positions)
    if (!is_finite(p)) std::abort();
  std::ostringstream written;
  write_mesh(out.mesh, written, Format::ply);
  return 0;
}
