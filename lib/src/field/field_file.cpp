// The .vfd file (docs/field.md, version 1). Little-endian; samples and the per-face cells
// are run-length coded (varint pairs: run, value), rank by rank, which is where adjacent
// samples repeat (the paper's §7.1 expectation, measured in docs/field.md).
#include <cmath>
#include <cstring>

#include "visimp/core/errors.h"
#include "visimp/field/field.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/byte_stream.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

constexpr char kMagic[8] = {'V', 'I', 'S', 'F', 'I', 'E', 'L', 'D'};
constexpr std::uint32_t kVersion = 1;

void put_f32(ByteWriter& w, float v) {
  std::uint32_t bits;
  std::memcpy(&bits, &v, 4);
  w.u32(bits);
}
float get_f32(ByteReader& r) {
  const std::uint32_t bits = r.u32();
  float v;
  std::memcpy(&v, &bits, 4);
  return v;
}

// Runs of equal values in `values`, read with `stride` starting at `first`.
void encode_runs(const std::vector<std::uint32_t>& values, std::size_t first, std::size_t stride, ByteWriter& w) {
  std::size_t i = first;
  while (i < values.size()) {
    const std::uint32_t v = values[i];
    std::uint64_t run = 0;
    while (i < values.size() && values[i] == v) {
      ++run;
      i += stride;
    }
    w.varint(run);
    w.varint(v);
  }
}

void decode_runs(ByteReader& r, std::vector<std::uint32_t>& values, std::size_t first, std::size_t stride,
                 std::uint32_t limit, const std::string& path, const char* what) {
  std::size_t i = first;
  const std::size_t count = values.size() <= first ? 0 : (values.size() - first + stride - 1) / stride;
  std::size_t done = 0;
  while (done < count) {
    const std::uint64_t run = r.varint();
    const std::uint64_t v = r.varint();
    if (run == 0 || run > count - done) throw IoError(path, std::string("a run of ") + what + " overruns its array");
    if (v > limit) throw IoError(path, std::string(what) + " value " + std::to_string(v) + " is out of range");
    for (std::uint64_t k = 0; k < run; ++k, i += stride) values[i] = static_cast<std::uint32_t>(v);
    done += run;
  }
}

ByteWriter encode(const VisibilityField& field, FieldFileSizes& sizes) {
  ByteWriter w;
  w.bytes.assign(kMagic, kMagic + 8);
  w.u32(kVersion);
  w.u64(field.mesh_hash);
  w.u64(field.faces);
  w.u64(field.vertices);
  const FieldOptions& o = field.options;
  w.u32(static_cast<std::uint32_t>(o.cells.mode));
  for (int v : {o.cells.grid, o.uv, o.st, o.ids, o.slabs, o.layers}) w.u32(static_cast<std::uint32_t>(v));
  for (const Vec3& p : {field.box.min, field.box.max}) {
    w.f64(p.x);
    w.f64(p.y);
    w.f64(p.z);
  }
  w.f64(field.seconds_build);
  w.u64(field.rays);
  w.u64(field.cells.objects);
  w.u64(field.cells.num_cells());
  for (std::size_t c = 0; c < field.cells.num_cells(); ++c) {
    const CellKey& k = field.cells.keys[c];
    w.u32(k.object);
    w.u32(std::uint32_t{k.cx} | std::uint32_t{k.cy} << 8 | std::uint32_t{k.cz} << 16);
    const BoundingBox& b = field.cells.bounds[c];
    for (double v : {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z}) put_f32(w, static_cast<float>(v));
  }
  encode_runs(field.cells.face_cell, 0, 1, w);
  for (const Slab& s : field.slabs) {
    w.u32(static_cast<std::uint32_t>(s.axis));
    w.u32(s.side > 0 ? 1 : 0);
    for (double v : {s.plane, s.s_range[0], s.s_range[1], s.t_range[0], s.t_range[1]}) w.f64(v);
    for (double v : s.starts) w.f64(v);
  }
  const std::size_t before = w.bytes.size();
  for (const auto& slab : field.samples) {
    for (const auto& layer : slab) {
      for (int rank = 0; rank < o.ids; ++rank)
        encode_runs(layer, static_cast<std::size_t>(rank), static_cast<std::size_t>(o.ids), w);
    }
  }
  sizes.coded_sample_bytes = w.bytes.size() - before;
  sizes.raw_sample_bytes = field.sample_bytes();
  w.bytes.append(reinterpret_cast<const char*>(field.interior.data()), field.interior.size());
  sizes.file_bytes = w.bytes.size();
  return w;
}

}  // namespace

FieldFileSizes measure_field_coding(const VisibilityField& field) {
  FieldFileSizes sizes;
  encode(field, sizes);
  return sizes;
}

FieldFileSizes write_field_file(const VisibilityField& field, const std::string& path) {
  FieldFileSizes sizes;
  const ByteWriter w = encode(field, sizes);
  AtomicFileWriter file(path);
  file.stream().write(w.bytes.data(), static_cast<std::streamsize>(w.bytes.size()));
  file.commit();
  return sizes;
}

VisibilityField read_field_file(const std::string& path) { return parse_field_file(read_file_bytes(path), path); }

VisibilityField parse_field_file(const std::string& bytes, const std::string& path) {
  ByteReader r(path, bytes, "visibility field");
  r.expect_magic(kMagic, "visimp visibility field (.vfd)");
  const std::uint32_t version = r.u32();
  if (version != kVersion) {
    throw IoError(path, "is a version " + std::to_string(version) + " visibility field; this visimp reads version " +
                            std::to_string(kVersion));
  }
  VisibilityField f;
  f.mesh_hash = r.u64();
  f.faces = r.u64();
  f.vertices = r.u64();
  FieldOptions& o = f.options;
  const std::uint32_t mode = r.u32();
  if (mode > 2) throw IoError(path, "unknown cell mode " + std::to_string(mode));
  o.cells.mode = static_cast<CellMode>(mode);
  for (int* v : {&o.cells.grid, &o.uv, &o.st, &o.ids, &o.slabs, &o.layers}) {
    const std::uint32_t x = r.u32();
    *v = x > 0xffff ? -1 : static_cast<int>(x);
  }
  try {
    check_options(o, f.faces);
  } catch (const UsageError& e) {
    throw IoError(path, std::string("holds bad options: ") + e.what());
  }
  for (Vec3* p : {&f.box.min, &f.box.max}) {
    p->x = r.f64();
    p->y = r.f64();
    p->z = r.f64();
  }
  if (!(f.box.min.x <= f.box.max.x && f.box.min.y <= f.box.max.y && f.box.min.z <= f.box.max.z) ||
      !std::isfinite(f.box.diagonal())) {
    throw IoError(path, "holds an empty or non-finite scene box");
  }
  f.seconds_build = r.f64();
  f.rays = r.u64();
  f.cells.objects = r.u64();
  const std::uint64_t cells = r.u64();
  if (f.faces == 0 || f.faces > 0xffffffffu || cells == 0 || cells > f.faces || f.cells.objects > f.faces) {
    throw IoError(path, "holds " + std::to_string(cells) + " cells for " + std::to_string(f.faces) + " faces");
  }
  // Runs can expand a few bytes into a lot: bound what the header claims before allocating
  // (a real file expands far less than 4096-fold plus 64 MiB).
  const std::uint64_t slabs = static_cast<std::uint64_t>(o.slabs) * static_cast<std::uint64_t>(o.layers);
  const std::uint64_t expanded = f.faces * 8 + slabs * f.samples_per_layer() * static_cast<std::uint64_t>(o.ids) * 4;
  if (expanded > 4096 * static_cast<std::uint64_t>(bytes.size()) + (std::uint64_t{64} << 20)) {
    throw IoError(path, "the header claims " + std::to_string(expanded) + " bytes of data from a " +
                            std::to_string(bytes.size()) + "-byte file");
  }
  if (r.remaining() < cells * 32) throw IoError(path, "is truncated in its cell table");
  f.cells.keys.resize(cells);
  f.cells.bounds.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    CellKey& k = f.cells.keys[c];
    k.object = r.u32();
    const std::uint32_t packed = r.u32();
    k.cx = packed & 0xff;
    k.cy = (packed >> 8) & 0xff;
    k.cz = (packed >> 16) & 0xff;
    BoundingBox& b = f.cells.bounds[c];
    b.min.x = get_f32(r), b.min.y = get_f32(r), b.min.z = get_f32(r);
    b.max.x = get_f32(r), b.max.y = get_f32(r), b.max.z = get_f32(r);
    if (k.object >= f.cells.objects || !(b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z) ||
        !std::isfinite(b.diagonal())) {
      throw IoError(path, "holds a bad record for cell " + std::to_string(c) + " (object or bounding box)");
    }
  }
  f.cells.face_cell.resize(f.faces);
  decode_runs(r, f.cells.face_cell, 0, 1, static_cast<std::uint32_t>(cells - 1), path, "face cell");
  // Derived: faces per cell (bounds came from the file); every cell must have some.
  f.cells.index_cell_faces();
  for (std::size_t c = 0; c < cells; ++c) {
    if (f.cells.cell_offsets[c + 1] == f.cells.cell_offsets[c])
      throw IoError(path, "holds cell " + std::to_string(c) + " without faces");
  }
  // Slabs are a function of the box and the options: a file must hold exactly those (so a
  // corrupt one cannot leave a direction without its slab or give a degenerate rectangle).
  f.slabs = place_slabs(f.box, o.slabs, o.layers);
  for (const Slab& expected : f.slabs) {
    const std::uint32_t axis = r.u32(), side = r.u32();
    bool same = axis == static_cast<std::uint32_t>(expected.axis) && side == (expected.side > 0 ? 1u : 0u);
    for (double v :
         {expected.plane, expected.s_range[0], expected.s_range[1], expected.t_range[0], expected.t_range[1]})
      same &= r.f64() == v;
    for (double v : expected.starts) same &= r.f64() == v;
    if (!same) throw IoError(path, "holds slabs that do not match its scene box and options");
  }
  f.samples.resize(f.slabs.size());
  for (auto& slab : f.samples) {
    slab.resize(static_cast<std::size_t>(o.layers));
    for (auto& layer : slab) {
      layer.assign(f.samples_per_layer() * static_cast<std::size_t>(o.ids), 0);
      for (int rank = 0; rank < o.ids; ++rank) {
        decode_runs(r, layer, static_cast<std::size_t>(rank), static_cast<std::size_t>(o.ids),
                    static_cast<std::uint32_t>(cells), path, "sample");
      }
    }
  }
  const std::size_t interior_bytes =
      VisibilityField::kOccupancy * VisibilityField::kOccupancy * VisibilityField::kOccupancy / 8;
  if (r.remaining() != interior_bytes) {
    throw IoError(path, "ends with " + std::to_string(r.remaining()) + " bytes where the interior grid takes " +
                            std::to_string(interior_bytes));
  }
  const std::string tail = r.text(interior_bytes);
  f.interior.assign(tail.begin(), tail.end());
  return f;
}

}  // namespace visimp
