// The .vbf format (see bitfield_file.h and docs/formats.md).
#include "visimp/patches/bitfield_file.h"

#include <cmath>

#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/byte_stream.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

constexpr char kMagic[8] = {'V', 'I', 'S', 'I', 'M', 'P', 'B', 'F'};
constexpr std::uint32_t kCompressed = 1, kPerFace = 2, kNeighbourFill = 4, kMapRuns = 8, kDepthTest = 16;
constexpr std::size_t kHeaderBytes = 120;

// Zero-run coding of the rows taken as one word sequence: repeated (zero words, literal
// words, the literals). A lone zero costs two bytes instead of eight.
void compress_words(const std::vector<std::uint64_t>& words, ByteWriter& out) {
  std::size_t i = 0;
  while (i < words.size()) {
    std::size_t zeros = 0;
    while (i + zeros < words.size() && words[i + zeros] == 0) ++zeros;
    std::size_t literals = 0;
    while (i + zeros + literals < words.size() && words[i + zeros + literals] != 0) ++literals;
    out.varint(zeros);
    out.varint(literals);
    for (std::size_t k = 0; k < literals; ++k) out.u64(words[i + zeros + k]);
    i += zeros + literals;
  }
}

void decompress_words(ByteReader& in, std::vector<std::uint64_t>& words, std::size_t end, const std::string& path) {
  std::size_t i = 0;
  while (in.position() < end) {
    const std::uint64_t zeros = in.varint(), literals = in.varint();
    if (zeros > words.size() - i || literals > words.size() - i - zeros) {
      throw IoError(path, "compressed bitfields run past " + std::to_string(words.size()) + " words");
    }
    i += zeros;  // already zero
    for (std::uint64_t k = 0; k < literals; ++k) words[i++] = in.u64();
  }
  if (i != words.size() || in.position() != end) {
    throw IoError(path,
                  "compressed bitfields hold " + std::to_string(i) + " of " + std::to_string(words.size()) + " words");
  }
}

// The face→patch map as (patch, run length) varint pairs: faces of one patch often follow
// each other in a mesh's face order.
void write_map_runs(const std::vector<std::uint32_t>& map, ByteWriter& out) {
  for (std::size_t i = 0; i < map.size();) {
    std::size_t j = i + 1;
    while (j < map.size() && map[j] == map[i]) ++j;
    out.varint(map[i]);
    out.varint(j - i);
    i = j;
  }
}

void read_map_runs(ByteReader& in, std::vector<std::uint32_t>& map, std::uint64_t units, const std::string& path) {
  for (std::size_t i = 0; i < map.size();) {
    const std::uint64_t patch = in.varint(), run = in.varint();
    if (patch >= units || run == 0 || run > map.size() - i) throw IoError(path, "malformed face→patch runs");
    std::fill_n(map.begin() + static_cast<std::ptrdiff_t>(i), run, static_cast<std::uint32_t>(patch));
    i += run;
  }
}

}  // namespace

BitfieldFileSizes write_bitfield_file(const BitfieldSet& set, const std::string& path, bool compress) {
  // (`compress` is cleared below when coding would not make the rows smaller.)
  if (set.bits.cameras != set.cameras.size() || (!set.per_face && set.face_patch.size() != set.faces) ||
      (set.per_face && set.bits.units != set.faces)) {
    throw UsageError("inconsistent bitfield set: its counts do not match");
  }
  ByteWriter body;
  body.bytes = set.cameras.name;
  for (const Vec3& d : set.cameras.directions) {
    body.f64(d.x);
    body.f64(d.y);
    body.f64(d.z);
  }
  BitfieldFileSizes sizes;
  sizes.directions = body.bytes.size();
  std::size_t before = body.bytes.size();
  write_map_runs(set.face_patch, body);
  const bool map_runs = body.bytes.size() - before < set.face_patch.size() * 4;
  if (!map_runs) {
    body.bytes.resize(before);
    for (std::uint32_t p : set.face_patch) body.u32(p);
  }
  sizes.patch_map = body.bytes.size() - before;
  before = body.bytes.size();
  if (compress) {
    compress_words(set.bits.words, body);
    // Rows without zero words do not shrink: then the plain words are stored.
    if (body.bytes.size() - before >= set.bits.words.size() * 8) {
      body.bytes.resize(before);
      compress = false;
    }
  }
  if (!compress) {
    for (std::uint64_t w : set.bits.words) body.u64(w);
  }
  sizes.bitfields = body.bytes.size() - before;
  sizes.bitfields_uncompressed = set.bits.words.size() * 8;

  ByteWriter head;
  head.bytes.assign(kMagic, kMagic + 8);
  head.u32(BitfieldSet::kVersion);
  head.u32((compress ? kCompressed : 0) | (set.per_face ? kPerFace : 0) | (set.neighbour_fill ? kNeighbourFill : 0) |
           (map_runs ? kMapRuns : 0) | (set.depth_test ? kDepthTest : 0));
  head.u64(set.mesh_hash);
  head.u64(set.faces);
  head.u64(set.bits.units);
  head.u64(set.cameras.size());
  head.u64(set.transparent_faces);
  head.u32(set.resolution);
  head.u32(static_cast<std::uint32_t>(set.cameras.name.size()));
  head.f64(set.center.x);
  head.f64(set.center.y);
  head.f64(set.center.z);
  head.f64(set.radius);
  head.u64(sizes.patch_map);
  head.u64(sizes.bitfields);
  head.u64(fnv1a(kFnvOffset, body.bytes.data(), body.bytes.size()));
  sizes.header = head.bytes.size();
  sizes.total = head.bytes.size() + body.bytes.size();
  AtomicFileWriter file(path);
  file.stream().write(head.bytes.data(), static_cast<std::streamsize>(head.bytes.size()));
  file.stream().write(body.bytes.data(), static_cast<std::streamsize>(body.bytes.size()));
  file.commit();
  return sizes;
}

BitfieldSet read_bitfield_file(const std::string& path) { return parse_bitfield_file(read_file_bytes(path), path); }

BitfieldSet parse_bitfield_file(const std::string& bytes, const std::string& path) {
  ByteReader r(path, bytes, "bitfield file");
  r.expect_magic(kMagic, "visimp bitfield file");
  BitfieldSet set;
  const std::uint32_t version = r.u32();
  if (version != BitfieldSet::kVersion) {
    throw IoError(path, "bitfield file version " + std::to_string(version) + "; this visimp reads version " +
                            std::to_string(BitfieldSet::kVersion));
  }
  const std::uint32_t flags = r.u32();
  set.per_face = flags & kPerFace;
  set.neighbour_fill = flags & kNeighbourFill;
  set.depth_test = flags & kDepthTest;
  set.mesh_hash = r.u64();
  set.faces = r.u64();
  const std::uint64_t units = r.u64(), cameras = r.u64();
  set.transparent_faces = r.u64();
  set.resolution = r.u32();
  const std::uint32_t name_length = r.u32();
  set.center = {r.f64(), r.f64(), r.f64()};
  set.radius = r.f64();
  const std::uint64_t map_bytes = r.u64(), bitfield_bytes = r.u64(), checksum = r.u64();
  if (r.position() != kHeaderBytes) throw std::logic_error("bitfield header size");

  const std::size_t body = r.remaining();
  if (fnv1a(kFnvOffset, bytes.data() + kHeaderBytes, body) != checksum) {
    throw IoError(path, "checksum mismatch: the bitfield file is damaged");
  }
  if (cameras == 0 || cameras > 65536 || units > set.faces || (set.per_face && units != set.faces) ||
      set.faces > 0xffffffffull || !std::isfinite(set.radius) || !(set.radius > 0) ||
      set.transparent_faces > set.faces) {
    throw IoError(path, "inconsistent counts in the bitfield header");
  }
  if ((set.per_face && map_bytes != 0) || (!set.per_face && !(flags & kMapRuns) && map_bytes != set.faces * 4)) {
    throw IoError(path, "the face→patch map has the wrong size");
  }
  if (name_length + cameras * 24 + map_bytes + bitfield_bytes != body) {
    throw IoError(path, "the bitfield file's size does not match its header");
  }
  // The header's counts are not under the checksum and the sections may be compressed: bound
  // what they expand to before allocating it (found by fuzz_read_vbf: 11 GB from 300 bytes).
  // Real files expand about 10-100-fold; 4096-fold plus 64 MiB is far beyond any of them.
  const std::uint64_t expanded = (set.per_face ? 0 : set.faces * 4) + cameras * ((units + 63) / 64) * 8;
  if (expanded > 4096 * static_cast<std::uint64_t>(bytes.size()) + (std::uint64_t{64} << 20)) {
    throw IoError(path, "the header claims " + std::to_string(expanded) + " bytes of data from a " +
                            std::to_string(bytes.size()) + "-byte file: damaged");
  }
  set.cameras.name = r.text(name_length);
  set.cameras.directions.resize(cameras);
  for (Vec3& d : set.cameras.directions) {
    d = {r.f64(), r.f64(), r.f64()};
    if (!(std::fabs(norm(d) - 1) < 1e-9)) throw IoError(path, "a camera direction is not a unit vector");
  }
  if (!set.per_face) {
    set.face_patch.resize(set.faces);
    const std::size_t map_end = r.position() + map_bytes;
    if (flags & kMapRuns) {
      read_map_runs(r, set.face_patch, units, path);
    } else {
      for (std::uint32_t& p : set.face_patch) {
        p = r.u32();
        if (p >= units) throw IoError(path, "a face's patch number is out of range");
      }
    }
    if (r.position() != map_end) throw IoError(path, "the face→patch map has the wrong size");
  }
  set.bits = Bitfields(units, cameras);
  if (flags & kCompressed) {
    decompress_words(r, set.bits.words, bytes.size(), path);
  } else {
    if (bitfield_bytes != set.bits.words.size() * 8) throw IoError(path, "the bitfield section has the wrong size");
    for (std::uint64_t& w : set.bits.words) w = r.u64();
  }
  // Bits past the last unit must be clear: a reader may count them.
  if (units % 64 != 0) {
    const std::uint64_t unused = ~std::uint64_t{0} << (units % 64);
    for (std::size_t c = 0; c < cameras; ++c) {
      if (set.bits.row(c)[set.bits.words_per_row - 1] & unused) throw IoError(path, "bits set beyond the last unit");
    }
  }
  return set;
}

void check_bitfields_match(const BitfieldSet& set, const Mesh& mesh, const std::string& path) {
  if (mesh.num_faces() != set.faces || hash_mesh(mesh) != set.mesh_hash) {
    throw IoError(path, "belongs to another mesh (" + std::to_string(set.faces) + " faces, hash " +
                            std::to_string(set.mesh_hash) + "; this one has " + std::to_string(mesh.num_faces()) +
                            " faces, hash " + std::to_string(hash_mesh(mesh)) + ")");
  }
}

}  // namespace visimp
