// libFuzzer target for visimp's own file readers (VISIMP_FUZZ_READER picks one): the tally
// of a camera slice (.bin), the patch bitfield file (.vbf), the camera list and the
// visibility field (.vfd). Invalid input
// must end in IoError (or UsageError for a well-formed file that breaks a contract); anything
// else — a crash, a sanitizer report, another exception, a hang, runaway memory — is a finding.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/errors.h"
#include "visimp/field/field.h"
#include "visimp/patches/bitfield_file.h"
#include "visimp/visibility/tally.h"

#define VISIMP_READER_tally 1
#define VISIMP_READER_vbf 2
#define VISIMP_READER_cameras 3
#define VISIMP_READER_vfd 4
#define VISIMP_CONCAT(a, b) a##b
#define VISIMP_READER_ID(name) VISIMP_CONCAT(VISIMP_READER_, name)

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
