// The patch-bitfield file (".vbf"; layout in docs/formats.md): everything view
// reconstruction needs without re-rendering — the sampling sphere, the camera directions,
// the face→patch map and one bitfield row per camera — plus a hash of the mesh it belongs
// to, so it is never applied to another mesh.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "visimp/cameras/camera_set.h"
#include "visimp/core/mesh.h"
#include "visimp/core/vec3.h"
#include "visimp/patches/bitfields.h"

namespace visimp {

struct BitfieldSet {
  static constexpr std::uint32_t kVersion = 1;

  std::uint64_t mesh_hash = 0;  ///< hash_mesh() of the mesh the bits describe
  std::uint64_t faces = 0;      ///< its face count
  bool per_face = false;        ///< units are faces (ID-bitfields), face_patch is empty
  bool neighbour_fill = false;
  bool depth_test = false;  ///< thin faces were set by the depth test
  std::uint64_t transparent_faces = 0;
  std::uint32_t resolution = 0;  ///< of the sampling frames
  Vec3 center;                   ///< the sampling sphere, in mesh coordinates
  double radius = 1;
  CameraSet cameras;
  std::vector<std::uint32_t> face_patch;  ///< per face, when !per_face
  Bitfields bits;                         ///< units × cameras

  /// Patch of face f (f itself for ID-bitfields).
  std::uint32_t unit_of(std::size_t f) const { return per_face ? static_cast<std::uint32_t>(f) : face_patch[f]; }
};

/// Everything a BitfieldSet says about how its bits were made, filled in one place (mesh hash
/// and faces, units, flags, sampling sphere, cameras, resolution); the bits themselves are
/// left empty for the caller to record. `per_face`: the units are the faces (ID-bitfields).
BitfieldSet make_bitfield_set(const Mesh& mesh, const PatchPartition& partition, bool per_face, const CameraSet& cameras,
                              int resolution, const BitfieldOptions& options);

struct BitfieldFileSizes {
  std::uint64_t header = 0, directions = 0, patch_map = 0, bitfields = 0, total = 0;
  std::uint64_t bitfields_uncompressed = 0;  ///< cameras × words × 8
};

/// Writes atomically; with `compress`, rows are stored as zero-word runs and literal words
/// (unless that is not smaller: then as plain words, and the file says so).
BitfieldFileSizes write_bitfield_file(const BitfieldSet& set, const std::string& path, bool compress);
/// Throws IoError naming the file for a wrong magic or version, truncation, a checksum
/// mismatch or inconsistent counts.
BitfieldSet read_bitfield_file(const std::string& path);
/// The same from bytes in memory; `path` names them in errors.
BitfieldSet parse_bitfield_file(const std::string& bytes, const std::string& path);
/// Throws IoError naming `path` when `mesh` is not the mesh the set was made for.
void check_bitfields_match(const BitfieldSet& set, const Mesh& mesh, const std::string& path);

}  // namespace visimp
