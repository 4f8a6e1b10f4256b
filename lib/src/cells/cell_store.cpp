// Cell files and the manifest (see cell_store.h).
#include "visimp/cells/cell_store.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/byte_stream.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

constexpr char kMagic[8] = {'V', 'I', 'S', 'C', 'E', 'L', 'L', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr const char* kManifestFormat = "visimp-cells";

std::uint32_t float_bits(float v) {
  std::uint32_t b;
  std::memcpy(&b, &v, 4);
  return b;
}

float bits_float(std::uint32_t b) {
  float v;
  std::memcpy(&v, &b, 4);
  return v;
}

std::uint32_t zigzag(int v) { return (static_cast<std::uint32_t>(v) << 1) ^ static_cast<std::uint32_t>(v >> 31); }
int unzigzag(std::uint64_t v) { return static_cast<int>((v >> 1) ^ (~(v & 1) + 1)); }

void write_vec(ByteWriter& w, const Vec3& v) {
  w.f64(v.x);
  w.f64(v.y);
  w.f64(v.z);
}

void write_texture(ByteWriter& w, const ProjectiveTexture& t) {
  write_vec(w, t.view.eye);
  write_vec(w, t.view.forward);
  write_vec(w, t.view.right);
  write_vec(w, t.view.up);
  w.f64(t.view.tan_half_fov);
  w.f64(t.view.near);
  for (int v : {t.view.resolution, t.x0, t.y0, t.width, t.height}) w.u32(static_cast<std::uint32_t>(v));
  w.u32(float_bits(t.near_distance));
  w.u32(float_bits(t.far_distance));
  w.bytes.append(reinterpret_cast<const char*>(t.y.data()), t.y.size());
  for (std::uint16_t d : t.depth) {
    w.bytes.push_back(static_cast<char>(d & 0xff));
    w.bytes.push_back(static_cast<char>(d >> 8));
  }
}

ProjectiveTexture read_texture(ByteReader& r, const std::string& path, const std::string& where) {
  ProjectiveTexture t;
  auto vec = [&] {
    Vec3 v;
    v.x = r.f64();
    v.y = r.f64();
    v.z = r.f64();
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw IoError(path, where + ": a texture view is not finite");
    return v;
  };
  t.view.eye = vec();
  t.view.forward = vec();
  t.view.right = vec();
  t.view.up = vec();
  t.view.tan_half_fov = r.f64();
  t.view.near = r.f64();
  if (!(t.view.tan_half_fov > 0 && t.view.tan_half_fov < 1e6) || !(t.view.near > 0) || !std::isfinite(t.view.near))
    throw IoError(path, where + ": a texture's field of view or near plane is out of range");
  int* fields[] = {&t.view.resolution, &t.x0, &t.y0, &t.width, &t.height};
  for (int* f : fields) {
    const std::uint32_t v = r.u32();
    if (v > 65536) throw IoError(path, where + ": a texture size is out of range");
    *f = static_cast<int>(v);
  }
  if (t.x0 + t.width > t.view.resolution || t.y0 + t.height > t.view.resolution)
    throw IoError(path, where + ": a texture's crop leaves its image");
  t.near_distance = bits_float(r.u32());
  t.far_distance = bits_float(r.u32());
  if (!std::isfinite(t.near_distance) || !std::isfinite(t.far_distance) || t.far_distance < t.near_distance)
    throw IoError(path, where + ": a texture's depth range is invalid");
  const std::size_t pixels = static_cast<std::size_t>(t.width) * static_cast<std::size_t>(t.height);
  if (pixels > r.remaining() / 3) throw IoError(path, where + ": a texture does not fit in the file");
  const std::string y = r.text(pixels), d = r.text(2 * pixels);
  t.y.assign(y.begin(), y.end());
  t.depth.resize(pixels);
  for (std::size_t k = 0; k < pixels; ++k)
    t.depth[k] = static_cast<std::uint16_t>(static_cast<unsigned char>(d[2 * k]) |
                                            (static_cast<unsigned char>(d[2 * k + 1]) << 8));
  return t;
}

}  // namespace

std::uint64_t hash_scene(const Scene& scene) {
  std::vector<std::uint64_t> mesh_hashes;
  for (const Mesh& m : scene.meshes) mesh_hashes.push_back(hash_mesh(m));
  std::uint64_t h = kFnvOffset;
  for (const SceneObject& o : scene.objects) {
    h = fnv1a(h, &mesh_hashes[o.mesh], sizeof(std::uint64_t));
    h = fnv1a(h, o.transform.data(), sizeof(Transform));
  }
  return h;
}

std::string cell_file_name(const HexCell& cell) {
  auto part = [](int v) { return v < 0 ? "m" + std::to_string(-static_cast<long>(v)) : std::to_string(v); };
  return "cell_" + part(cell.q) + "_" + part(cell.r) + ".vcell";
}

void write_cell(const CellLods& lods, std::uint64_t scene_hash, const std::string& path) {
  ByteWriter w;
  w.bytes.append(kMagic, 8);
  w.u32(kVersion);
  w.u64(scene_hash);
  w.u32(zigzag(lods.cell.q));
  w.u32(zigzag(lods.cell.r));
  w.varint(lods.entries.size());
  for (const CellEntry& e : lods.entries) {
    w.bytes.push_back(static_cast<char>(e.kind));
    w.varint(e.object);
    w.u32(float_bits(e.self_occluding_error));
    w.varint(e.source_faces);
    w.varint(e.cluster.size());
    for (std::uint32_t k : e.cluster) w.varint(k);
    if (e.kind == LodKind::in_cluster) continue;
    if (e.kind == LodKind::full) {
      w.varint(e.faces.size());
      std::uint32_t previous = 0;
      for (std::size_t k = 0; k < e.faces.size(); ++k) {
        w.varint(k == 0 ? e.faces[k] : e.faces[k] - previous - 1);
        previous = e.faces[k];
      }
    } else {
      w.varint(e.mesh.num_vertices());
      w.varint(e.mesh.num_faces());
      for (const Vec3& p : e.mesh.positions) {
        w.u32(float_bits(static_cast<float>(p.x)));
        w.u32(float_bits(static_cast<float>(p.y)));
        w.u32(float_bits(static_cast<float>(p.z)));
      }
      for (const Face& f : e.mesh.faces)
        for (VertexIndex v : f) w.varint(v);
      w.varint(e.textures.size());
      for (const ProjectiveTexture& t : e.textures) write_texture(w, t);
    }
  }
  w.u64(fnv1a(kFnvOffset, w.bytes.data(), w.bytes.size()));
  AtomicFileWriter out(path);
  out.stream().write(w.bytes.data(), static_cast<std::streamsize>(w.bytes.size()));
  out.commit();
}

CellLods parse_cell(const std::string& bytes, const std::string& path, const Scene& scene, std::uint64_t scene_hash,
                    const HexCell& expected) {
  ByteReader r(path, bytes, "cell file");
  r.expect_magic(kMagic, "visimp cell file");
  const std::uint32_t version = r.u32();
  if (version != kVersion)
    throw IoError(path, "cell file version " + std::to_string(version) + " (this visimp reads version 1)");
  if (bytes.size() < 8 + 8) throw IoError(path, "truncated cell file");
  const std::uint64_t stored = [&] {
    std::uint64_t h = 0;
    for (int i = 0; i < 8; ++i)
      h |= std::uint64_t{static_cast<unsigned char>(bytes[bytes.size() - 8 + static_cast<std::size_t>(i)])} << (8 * i);
    return h;
  }();
  if (stored != fnv1a(kFnvOffset, bytes.data(), bytes.size() - 8))
    throw IoError(path, "cell file is corrupt (its checksum does not match)");
  if (r.u64() != scene_hash) throw IoError(path, "cell file was built for another scene (content hash differs)");
  CellLods lods;
  lods.cell.q = unzigzag(r.u32());
  lods.cell.r = unzigzag(r.u32());
  if (lods.cell != expected)
    throw IoError(path, "holds cell (" + std::to_string(lods.cell.q) + ", " + std::to_string(lods.cell.r) +
                            "), expected (" + std::to_string(expected.q) + ", " + std::to_string(expected.r) + ")");
  const std::uint64_t count = r.varint();
  if (count != scene.objects.size())
    throw IoError(path, "cell file has " + std::to_string(count) + " entries for a scene of " +
                            std::to_string(scene.objects.size()) + " objects");
  lods.entries.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    CellEntry& e = lods.entries[i];
    const std::string where = "entry " + std::to_string(i);
    const auto kind = static_cast<std::uint8_t>(r.text(1)[0]);
    if (kind > 3) throw IoError(path, where + " has an unknown kind " + std::to_string(kind));
    e.kind = static_cast<LodKind>(kind);
    if (r.varint() != i) throw IoError(path, where + " names another object");
    e.object = static_cast<std::uint32_t>(i);
    e.self_occluding_error = bits_float(r.u32());
    if (!std::isfinite(e.self_occluding_error)) throw IoError(path, where + " has a non-finite s");
    e.source_faces = static_cast<std::uint32_t>(r.varint());
    const std::uint64_t members = r.varint();
    if (members > count) throw IoError(path, where + " names more cluster members than there are objects");
    for (std::uint64_t k = 0; k < members; ++k) {
      const std::uint64_t m = r.varint();
      if (m >= count) throw IoError(path, where + ": a cluster member is out of range");
      e.cluster.push_back(static_cast<std::uint32_t>(m));
    }
    if (e.kind == LodKind::in_cluster) {
      if (members != 1) throw IoError(path, where + " is in a cluster but does not name one holder");
      continue;
    }
    if (!e.cluster.empty() && (e.kind != LodKind::svmesh || e.cluster.front() != i))
      throw IoError(path, where + " holds a cluster but is not its first member's SVMesh");
    if (e.kind == LodKind::full) {
      const std::size_t object_faces = scene.meshes[scene.objects[i].mesh].num_faces();
      const std::uint64_t n = r.varint();
      if (n > object_faces || n > r.remaining())
        throw IoError(path, where + " keeps " + std::to_string(n) + " faces of an object of " +
                                std::to_string(object_faces));
      e.faces.resize(n);
      std::uint64_t next = 0;
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint64_t f = next + r.varint();
        if (f >= object_faces) throw IoError(path, where + ": face index out of range");
        e.faces[k] = static_cast<std::uint32_t>(f);
        next = f + 1;
      }
    } else {
      const std::uint64_t nv = r.varint(), nf = r.varint();
      if (nv > r.remaining() / 12 || nf > r.remaining() / 3)
        throw IoError(path, where + ": " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                                " faces do not fit in the file");
      e.mesh.positions.resize(nv);
      for (Vec3& p : e.mesh.positions) {
        p.x = bits_float(r.u32());
        p.y = bits_float(r.u32());
        p.z = bits_float(r.u32());
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          throw IoError(path, where + " has a non-finite position");
      }
      e.mesh.faces.resize(nf);
      for (Face& f : e.mesh.faces) {
        for (VertexIndex& v : f) {
          const std::uint64_t index = r.varint();
          if (index >= nv) throw IoError(path, where + ": vertex index out of range");
          v = static_cast<VertexIndex>(index);
        }
      }
      const std::uint64_t textures = r.varint();
      if (textures > 64) throw IoError(path, where + " has " + std::to_string(textures) + " textures (at most 64)");
      for (std::uint64_t k = 0; k < textures; ++k) e.textures.push_back(read_texture(r, path, where));
    }
  }
  if (r.remaining() != 8) throw IoError(path, "cell file has " + std::to_string(r.remaining() - 8) + " bytes too many");
  // Clusters agree: a member names a holder whose cluster lists it, and every listed member
  // but the holder says it is in that cluster.
  for (const CellEntry& e : lods.entries) {
    const std::string where = "entry " + std::to_string(e.object);
    if (e.kind == LodKind::in_cluster) {
      const CellEntry& holder = lods.entries[e.cluster.front()];
      if (std::find(holder.cluster.begin(), holder.cluster.end(), e.object) == holder.cluster.end())
        throw IoError(path, where + " names a cluster that does not list it");
    } else if (!e.cluster.empty()) {
      for (std::size_t k = 1; k < e.cluster.size(); ++k) {
        const CellEntry& m = lods.entries[e.cluster[k]];
        if (m.kind != LodKind::in_cluster || m.cluster.front() != e.object)
          throw IoError(path, where + " lists a cluster member that is not in it");
      }
    }
  }
  return lods;
}

CellLods read_cell(const std::string& path, const Scene& scene, std::uint64_t scene_hash, const HexCell& expected) {
  const std::string bytes = read_file_bytes(path);
  return parse_cell(bytes, path, scene, scene_hash, expected);
}

void write_manifest(const CellManifest& m, const std::string& path) {
  nlohmann::json j;
  j["format"] = kManifestFormat;
  j["version"] = 1;
  std::ostringstream hash;
  hash << std::hex << m.scene_hash;
  j["scene_hash"] = hash.str();
  j["objects"] = m.objects;
  j["grid"] = {{"cell_size", m.cell_size}, {"eye_height", m.eye_height}, {"origin", {m.origin_x, m.origin_y}}};
  j["options"] = {{"ts", m.options.ts_pixels},
                  {"tl", m.options.tl_pixels},
                  {"resolution", m.options.output_resolution},
                  {"fov", m.options.fov_degrees},
                  {"max_capture", m.options.max_capture_resolution},
                  {"base_levels", m.options.base_levels},
                  {"textures", m.options.textures},
                  {"max_texture", m.options.max_texture_resolution},
                  {"clustering", m.options.clustering},
                  {"max_cluster", m.options.max_cluster}};
  nlohmann::json cells = nlohmann::json::array();
  for (std::size_t i = 0; i < m.cells.size(); ++i) {
    cells.push_back({{"q", m.cells[i].q},
                     {"r", m.cells[i].r},
                     {"file", cell_file_name(m.cells[i])},
                     {"faces", i < m.cell_faces.size() ? m.cell_faces[i] : 0},
                     {"seconds", i < m.cell_seconds.size() ? m.cell_seconds[i] : 0.0}});
  }
  j["cells"] = cells;
  j["seconds"] = m.seconds;
  AtomicFileWriter out(path);
  out.stream() << j.dump(1) << '\n';
  out.commit();
}

CellManifest read_manifest(const std::string& path) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(read_file_bytes(path));
  } catch (const nlohmann::json::exception& e) {
    throw IoError(path, std::string("not a valid cells manifest: ") + e.what());
  }
  try {
    if (!j.is_object() || j.value("format", "") != kManifestFormat)
      throw IoError(path, "not a visimp cells manifest (format is not \"visimp-cells\")");
    if (j.at("version").get<int>() != 1)
      throw IoError(path, "cells manifest version " + j.at("version").dump() + " (this visimp reads version 1)");
    CellManifest m;
    m.scene_hash = std::stoull(j.at("scene_hash").get<std::string>(), nullptr, 16);
    m.objects = j.at("objects").get<std::size_t>();
    const auto& g = j.at("grid");
    m.cell_size = g.at("cell_size").get<double>();
    m.eye_height = g.at("eye_height").get<double>();
    m.origin_x = g.at("origin").at(0).get<double>();
    m.origin_y = g.at("origin").at(1).get<double>();
    const auto& o = j.at("options");
    m.options.ts_pixels = o.at("ts").get<double>();
    m.options.tl_pixels = o.at("tl").get<double>();
    m.options.output_resolution = o.at("resolution").get<int>();
    m.options.fov_degrees = o.at("fov").get<double>();
    m.options.max_capture_resolution = o.at("max_capture").get<int>();
    m.options.base_levels = o.at("base_levels").get<int>();
    m.options.textures = o.value("textures", false);
    m.options.max_texture_resolution = o.value("max_texture", 256);
    m.options.clustering = o.value("clustering", false);
    m.options.max_cluster = o.value("max_cluster", 8);
    for (const auto& c : j.at("cells")) {
      m.cells.push_back({c.at("q").get<int>(), c.at("r").get<int>()});
      m.cell_faces.push_back(c.value("faces", std::size_t{0}));
      m.cell_seconds.push_back(c.value("seconds", 0.0));
    }
    m.seconds = j.value("seconds", 0.0);
    (void)m.grid();  // throws for a bad size or height
    check_options(m.options);
    return m;
  } catch (const nlohmann::json::exception& e) {
    throw IoError(path, std::string("malformed cells manifest: ") + e.what());
  } catch (const UsageError& e) {  // before invalid_argument, its base
    throw IoError(path, std::string("cells manifest has a bad value: ") + e.what());
  } catch (const std::invalid_argument&) {
    throw IoError(path, "malformed cells manifest: scene_hash is not a hexadecimal number");
  } catch (const std::out_of_range&) {
    throw IoError(path, "malformed cells manifest: scene_hash is out of range");
  }
}

}  // namespace visimp
