// libFuzzer target for visimp's own file readers (VISIMP_FUZZ_READER picks one): the tally
// of a camera slice (.bin), the patch bitfield file (.vbf), the camera list and the
// visibility field (.vfd) and the walkthrough cell file (.vcell). Invalid input
// must end in IoError (or UsageError for a well-formed file that breaks a contract); anything
// else — a crash, a sanitizer report, another exception, a hang, runaway memory — is a finding.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "visimp/cameras/camera_set.h"
#include "visimp/cells/cell_store.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"
#include "visimp/field/field.h"
#include "visimp/patches/bitfield_file.h"
#include "visimp/visibility/tally.h"

#define VISIMP_READER_tally 1
#define VISIMP_READER_vbf 2
#define VISIMP_READER_cameras 3
#define VISIMP_READER_vfd 4
#define VISIMP_READER_vcell 5
#define VISIMP_CONCAT(a, b) a##b
#define VISIMP_READER_ID(name) VISIMP_CONCAT(VISIMP_READER_, name)

#if VISIMP_READER_ID(VISIMP_FUZZ_READER) == VISIMP_READER_vcell
namespace {
// The scene the cell files of corpus/vcell were built for: three tetrahedra (the first inside
// cell (0, 0)); the corpus is write_cell() of CellLodBuilder on it (cell size 5, eye height 0.5,
// 64² output, with and without textures), less the last 8 bytes.
const visimp::Scene& fuzz_scene() {
  static const visimp::Scene scene = [] {
    visimp::Scene s;
    visimp::Mesh tetra;
    tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    tetra.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    s.meshes.push_back(tetra);
    s.mesh_paths.push_back("tetra");
    for (double x : {0.0, 30.0, 300.0})
      s.objects.push_back({"tetra", 0, {1, 0, 0, x, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}});
    return s;
  }();
  return scene;
}
}  // namespace
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace visimp;
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  try {
#if VISIMP_READER_ID(VISIMP_FUZZ_READER) == VISIMP_READER_tally
    const VisibilityTally t = VisibilityTally::parse(bytes, "fuzz-input");
    if (t.seen.size() != t.total.size()) std::abort();
    for (std::size_t i = 0; i < t.seen.size(); ++i)
      if (t.seen[i] > t.total[i]) std::abort();
#elif VISIMP_READER_ID(VISIMP_FUZZ_READER) == VISIMP_READER_vbf
    const BitfieldSet set = parse_bitfield_file(bytes, "fuzz-input");
    if (set.bits.words.size() != set.bits.words_per_row * set.bits.cameras) std::abort();
#elif VISIMP_READER_ID(VISIMP_FUZZ_READER) == VISIMP_READER_vfd
    const VisibilityField field = parse_field_file(bytes, "fuzz-input");
    const std::size_t cells = field.cells.num_cells();
    if (field.cells.face_cell.size() != field.faces || field.cells.cell_faces.size() != field.faces) std::abort();
    for (std::uint32_t c : field.cells.face_cell)
      if (c >= cells) std::abort();
    for (const auto& slab : field.samples)
      for (const auto& layer : slab)
        for (std::uint32_t id : layer)
          if (id > cells) std::abort();
#elif VISIMP_READER_ID(VISIMP_FUZZ_READER) == VISIMP_READER_vcell
    // The input is a cell file without its checksum, and its scene hash is set to the fuzz
    // scene's: the structure behind both checks is what is fuzzed.
    const Scene& scene = fuzz_scene();
    const std::uint64_t hash = hash_scene(scene);
    std::string file = bytes;
    if (file.size() >= 20)
      for (int i = 0; i < 8; ++i) file[12 + static_cast<std::size_t>(i)] = static_cast<char>((hash >> (8 * i)) & 0xff);
    const std::uint64_t sum = fnv1a(kFnvOffset, file.data(), file.size());
    for (int i = 0; i < 8; ++i) file.push_back(static_cast<char>((sum >> (8 * i)) & 0xff));
    const CellLods lods = parse_cell(file, "fuzz-input", scene, hash, {0, 0});
    if (lods.entries.size() != scene.objects.size()) std::abort();
    for (const CellEntry& e : lods.entries) {
      for (std::uint32_t f : e.faces)
        if (f >= scene.meshes[0].num_faces()) std::abort();
      for (const Face& f : e.mesh.faces)
        for (VertexIndex v : f)
          if (v >= e.mesh.num_vertices()) std::abort();
      for (const ProjectiveTexture& t : e.textures) {
        if (t.y.size() != static_cast<std::size_t>(t.width) * t.height || t.depth.size() != t.y.size()) std::abort();
        float grey;
        (void)t.sample(Vec3{0.2, 0.2, 0.2}, 0.02, &grey);  // in range by construction
      }
    }
#else
    const CameraSet cameras = parse_camera_list(bytes, "fuzz-input");
    if (cameras.directions.empty()) std::abort();
    for (const Vec3& d : cameras.directions)
      if (!(std::abs(norm(d) - 1) < 1e-9)) std::abort();
#endif
  } catch (const IoError&) {
  } catch (const UsageError&) {
  }
  return 0;
}
