// Scenes: the JSON format, meshes as scenes, and statuary parks (see scene.h).
#include "visimp/cells/scene.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>

#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/core/portable_random.h"
#include "visimp/core/union_find.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/mesh_io.h"
#include "visimp/io/obj.h"
#include "visimp/core/validate.h"

namespace visimp {

Vec3 transform_point(const Transform& t, const Vec3& p) {
  return {t[0] * p.x + t[1] * p.y + t[2] * p.z + t[3], t[4] * p.x + t[5] * p.y + t[6] * p.z + t[7],
          t[8] * p.x + t[9] * p.y + t[10] * p.z + t[11]};
}

Transform multiply(const Transform& a, const Transform& b) {
  Transform out{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
        out[static_cast<std::size_t>(4 * i + j)] +=
            a[static_cast<std::size_t>(4 * i + k)] * b[static_cast<std::size_t>(4 * k + j)];
  return out;
}

Mesh Scene::object_mesh(std::size_t i) const { return transformed(meshes[objects[i].mesh], objects[i].transform); }

Mesh transformed(const Mesh& mesh, const Transform& t) {
  Mesh out = mesh;
  for (Vec3& p : out.positions) p = transform_point(t, p);
  // A mirroring transform turns faces inside out: rewind them so normals stay outward.
  const double det =
      t[0] * (t[5] * t[10] - t[6] * t[9]) - t[1] * (t[4] * t[10] - t[6] * t[8]) + t[2] * (t[4] * t[9] - t[5] * t[8]);
  if (det < 0) {
    for (Face& f : out.faces) std::swap(f[1], f[2]);
  }
  return out;
}

std::size_t Scene::face_count() const {
  std::size_t n = 0;
  for (const SceneObject& o : objects) n += meshes[o.mesh].num_faces();
  return n;
}

namespace {

Scene mesh_as_scene(const std::string& path) {
  // A file with more than one group (OBJ o/g, a scene file's nodes): the groups are the
  // objects. Otherwise the connected components (over shared vertices) are.
  FaceGroups groups;
  const Mesh mesh = read_mesh_with_groups(path, groups);
  const bool by_group = groups.names.size() > 1;
  Scene scene;
  scene.mesh_paths.push_back(path);
  UnionFind sets(mesh.num_vertices());
  if (!by_group) {
    for (const Face& f : mesh.faces) {
      sets.unite(f[0], f[1]);
      sets.unite(f[0], f[2]);
    }
  }
  std::map<std::uint32_t, std::size_t> component;
  std::vector<std::vector<VertexIndex>> remap;
  std::vector<std::uint32_t> object_key;
  for (std::size_t fi = 0; fi < mesh.faces.size(); ++fi) {
    const Face& f = mesh.faces[fi];
    const std::uint32_t key = by_group ? groups.face_group[fi] : sets.find(f[0]);
    const auto [it, added] = component.emplace(key, scene.meshes.size());
    if (added) object_key.push_back(key);
    if (added) {
      scene.meshes.emplace_back();
      remap.emplace_back(mesh.num_vertices(), ~VertexIndex{0});
    }
    Mesh& part = scene.meshes[it->second];
    std::vector<VertexIndex>& map = remap[it->second];
    Face g;
    for (int k = 0; k < 3; ++k) {
      VertexIndex& m = map[f[static_cast<std::size_t>(k)]];
      if (m == ~VertexIndex{0}) {
        m = static_cast<VertexIndex>(part.positions.size());
        part.positions.push_back(mesh.positions[f[static_cast<std::size_t>(k)]]);
      }
      g[static_cast<std::size_t>(k)] = m;
    }
    part.faces.push_back(g);
  }
  scene.mesh_paths.assign(scene.meshes.size(), path);
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    const std::string name = by_group ? groups.names[object_key[i]] : "";
    scene.objects.push_back({name.empty() ? (by_group ? "group_" : "component_") + std::to_string(i) : name, i,
                             kIdentity});
  }
  return scene;
}

}  // namespace

Scene parse_scene(const std::string& text, const std::string& path) {
  using nlohmann::json;
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    throw IoError(path, std::string("is not valid JSON: ") + e.what());
  }
  if (!doc.is_object() || doc.value("format", std::string()) != "visimp-scene")
    throw IoError(path, "is not a visimp scene (no \"format\": \"visimp-scene\")");
  if (!doc.contains("version") || !doc["version"].is_number_integer() || doc["version"].get<int>() != 1)
    throw IoError(path, "is a scene of an unknown version (this visimp reads version 1)");
  if (!doc.contains("objects") || !doc["objects"].is_array()) throw IoError(path, "has no \"objects\" array");
  Scene scene;
  scene.directory = std::filesystem::path(path).parent_path().string();
  std::map<std::string, std::size_t> mesh_index;
  std::size_t i = 0;
  for (const json& o : doc["objects"]) {
    const std::string where = "object " + std::to_string(i);
    if (!o.is_object() || !o.contains("mesh") || !o["mesh"].is_string())
      throw IoError(path, where + " has no \"mesh\" path");
    SceneObject object;
    object.name = o.contains("name") && o["name"].is_string() ? o["name"].get<std::string>() : where;
    if (o.contains("transform")) {
      const json& t = o["transform"];
      if (!t.is_array() || t.size() != 16) throw IoError(path, where + ": \"transform\" must hold 16 numbers");
      for (std::size_t k = 0; k < 16; ++k) {
        if (!t[k].is_number() || !std::isfinite(t[k].get<double>()))
          throw IoError(path, where + ": \"transform\" must hold 16 finite numbers");
        object.transform[k] = t[k].get<double>();
      }
      if (object.transform[12] != 0 || object.transform[13] != 0 || object.transform[14] != 0 ||
          object.transform[15] != 1)
        throw IoError(path, where + ": \"transform\" must be affine (last row 0 0 0 1)");
    }
    const std::string mesh = o["mesh"].get<std::string>();
    const auto [it, added] = mesh_index.emplace(mesh, scene.mesh_paths.size());
    if (added) {
      scene.mesh_paths.push_back(mesh);
      const std::filesystem::path file = std::filesystem::path(scene.directory) / mesh;
      scene.meshes.push_back(read_mesh(std::filesystem::path(mesh).is_absolute() ? mesh : file.string()));
    }
    object.mesh = it->second;
    scene.objects.push_back(std::move(object));
    ++i;
  }
  return scene;
}

Scene read_scene(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".json") return mesh_as_scene(path);
  return parse_scene(read_file_bytes(path), path);
}

void write_scene(const Scene& scene, const std::string& path) {
  nlohmann::json doc = {{"format", "visimp-scene"}, {"version", 1}, {"objects", nlohmann::json::array()}};
  for (const SceneObject& o : scene.objects) {
    doc["objects"].push_back({{"name", o.name}, {"mesh", scene.mesh_paths[o.mesh]}, {"transform", o.transform}});
  }
  AtomicFileWriter file(path);
  file.stream() << doc.dump(1) << '\n';
  file.commit();
}

Scene make_park(const std::vector<std::string>& meshes, const std::vector<bool>& z_up, const ParkOptions& o) {
  if (meshes.empty()) throw UsageError("a park needs at least one mesh");
  if ((o.objects == 0 && o.faces == 0) || !(o.width > 0) || !(o.depth > 0) || !(o.object_size > 0))
    throw UsageError("a park needs objects > 0 (or a face total) and a positive area and object size");
  Scene scene;
  for (const std::string& m : meshes) {
    scene.mesh_paths.push_back(std::filesystem::absolute(m).string());
    scene.meshes.push_back(read_mesh(m));
  }
  SplitMix64 random(o.seed);
  auto below = [&](std::size_t n) { return static_cast<std::size_t>(random.next() % n); };
  // With a face total, the meshes are drawn first (their own stream) until it is reached.
  std::vector<std::size_t> drawn;
  std::size_t objects = o.objects;
  if (o.faces > 0) {
    SplitMix64 pick(o.seed ^ 0x9e3779b97f4a7c15ull);
    std::size_t total = 0;
    while (total < o.faces) {
      if (drawn.size() >= 1000000) throw UsageError("a park of that many faces needs over a million objects");
      drawn.push_back(static_cast<std::size_t>(pick.next() % meshes.size()));
      total += scene.meshes[drawn.back()].num_faces();
      if (scene.meshes[drawn.back()].num_faces() == 0 && drawn.size() > 1000) break;
    }
    objects = drawn.size();
  }
  // A jittered grid with at least `objects` spots, filled in a random order.
  const std::size_t columns =
      static_cast<std::size_t>(std::ceil(std::sqrt(static_cast<double>(objects) * o.width / o.depth)));
  const std::size_t rows = (objects + columns - 1) / columns;
  std::vector<std::size_t> spots(columns * rows);
  for (std::size_t k = 0; k < spots.size(); ++k) spots[k] = k;
  for (std::size_t k = spots.size(); k > 1; --k) std::swap(spots[k - 1], spots[below(k)]);
  const double cell_w = o.width / static_cast<double>(columns), cell_d = o.depth / static_cast<double>(rows);
  for (std::size_t i = 0; i < objects; ++i) {
    const std::size_t m = drawn.empty() ? below(meshes.size()) : drawn[i];
    const BoundingBox box = bounding_box(scene.meshes[m]);
    const double scale = o.object_size * (0.8 + 0.4 * random.uniform()) / std::max(box.diagonal(), 1e-30);
    // Upright: Y-up meshes turn +90° about x (y → z); then the base goes to z = 0.
    Transform up = kIdentity;
    const bool zu = m < z_up.size() && z_up[m];
    if (!zu) up = {1, 0, 0, 0, 0, 0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1};
    const Vec3 lo = transform_point(up, box.min), hi = transform_point(up, box.max);
    const Vec3 base{0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), std::min(lo.z, hi.z)};
    const Transform centre = {1, 0, 0, -base.x, 0, 1, 0, -base.y, 0, 0, 1, -base.z, 0, 0, 0, 1};
    const double a = 2 * M_PI * random.uniform(), c = std::cos(a), s = std::sin(a);
    const std::size_t spot = spots[i];
    const double x = (static_cast<double>(spot % columns) + 0.25 + 0.5 * random.uniform()) * cell_w - 0.5 * o.width;
    const double y = (static_cast<double>(spot / columns) + 0.25 + 0.5 * random.uniform()) * cell_d - 0.5 * o.depth;
    const Transform place = {c * scale, -s * scale, 0, x, s * scale, c * scale, 0, y, 0, 0, scale, 0, 0, 0, 0, 1};
    scene.objects.push_back({std::filesystem::path(meshes[m]).stem().string() + "_" + std::to_string(i), m,
                             multiply(place, multiply(centre, up))});
  }
  return scene;
}

}  // namespace visimp
