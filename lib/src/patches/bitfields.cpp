// Recording patch/ID bitfields from ID frames (see bitfields.h).
//
// Rows belong to cameras and every camera is rendered by exactly one worker, so workers
// write disjoint words and need no locks; the result does not depend on the thread count.
#include "visimp/patches/bitfields.h"
#include "visimp/patches/bitfield_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "visimp/core/bounding_box.h"
#include "visimp/core/content_hash.h"
#include "visimp/core/errors.h"

namespace visimp {

Bitfields::Bitfields(std::size_t unit_count, std::size_t camera_count)
    : units(unit_count),
      cameras(camera_count),
      words_per_row((unit_count + 63) / 64),
      words(words_per_row * camera_count, 0) {}

std::size_t Bitfields::count(std::size_t camera) const {
  std::size_t n = 0;
  const std::uint64_t* r = row(camera);
  for (std::size_t w = 0; w < words_per_row; ++w) n += static_cast<std::size_t>(__builtin_popcountll(r[w]));
  return n;
}

BitfieldRecorder::BitfieldRecorder(const Mesh& mesh, const RenderScene& scene,
                                   std::vector<std::uint32_t> scene_face_input, const PatchPartition& partition,
                                   std::size_t cameras, const BitfieldOptions& options)
    : mesh_(mesh),
      scene_faces_(scene.faces),
      scene_face_input_(std::move(scene_face_input)),
      partition_(partition),
      options_(options),
      bits_(partition.patch_count(), cameras) {
  if (partition.face_patch.size() != mesh.num_faces()) {
    throw UsageError("the patch partition has " + std::to_string(partition.face_patch.size()) + " faces, the mesh " +
                     std::to_string(mesh.num_faces()));
  }
  if (scene_face_input_.size() != scene.faces.size()) {
    throw UsageError("the scene-to-input face map does not match the scene's faces");
  }
  if (!options_.transparent.empty() && options_.transparent.size() != mesh.num_faces()) {
    throw UsageError("the transparent-face flags do not match the mesh's face count");
  }
  if (options_.neighbour_fill) neighbours_ = face_neighbours(mesh);
  if (options_.neighbour_fill || options_.depth_test) {
    normals_.resize(mesh.num_faces());
    for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
      const Vec3 n = face_normal_unnormalized(mesh, mesh.faces[f]);
      const double length = norm(n);
      const Vec3 unit = length > 0 ? n / length : Vec3{};
      normals_[f] = {static_cast<float>(unit.x), static_cast<float>(unit.y), static_cast<float>(unit.z)};
    }
  }
}

void BitfieldRecorder::begin(unsigned workers) { workers_.resize(workers); }

namespace {

// Per scene vertex: not behind the depth buffer by more than `tolerance` at one of the 4
// pixel centres around its projection.
void mark_visible_vertices(const Frame& frame, float tolerance, std::vector<std::uint8_t>& visible) {
  const int r = frame.resolution();
  visible.assign(frame.vertices.size(), 0);
  for (std::size_t v = 0; v < frame.vertices.size(); ++v) {
    const ScreenVertex& s = frame.vertices[v];
    const int i0 = static_cast<int>(std::floor(s.x - 0.5f)), j0 = static_cast<int>(std::floor(s.y - 0.5f));
    for (int j = j0; j <= j0 + 1 && !visible[v]; ++j) {
      for (int i = i0; i <= i0 + 1; ++i) {
        if (i < 0 || j < 0 || i >= r || j >= r) continue;
        if (s.depth <=
            frame.depth[static_cast<std::size_t>(j) * static_cast<std::size_t>(r) + static_cast<std::size_t>(i)] +
                tolerance) {
          visible[v] = 1;
          break;
        }
      }
    }
  }
}

}  // namespace

void BitfieldRecorder::consume(const Frame& frame, std::size_t camera, unsigned worker) {
  std::uint64_t* row = bits_.row(camera);
  const std::uint32_t* face_patch = partition_.face_patch.data();
  const std::uint32_t* input = scene_face_input_.data();
  if (!options_.neighbour_fill && !options_.depth_test) {
    // Runs of one ID are common: look a face up once per run.
    std::uint32_t last = 0;
    for (std::uint32_t id : frame.ids) {
      if (id == last || id == 0) continue;
      last = id;
      const std::uint32_t unit = face_patch[input[id - 1]];
      row[unit >> 6] |= std::uint64_t{1} << (unit & 63);
    }
    return;
  }
  Worker& w = workers_[worker];
  if (w.seen_in_frame.empty()) w.seen_in_frame.assign(mesh_.num_faces(), 0);
  const std::uint32_t frame_number = ++w.frame_number;
  std::uint32_t* seen = w.seen_in_frame.data();
  std::uint32_t last = 0;
  for (std::uint32_t id : frame.ids) {
    if (id == last || id == 0) continue;
    last = id;
    seen[input[id - 1]] = frame_number;
  }
  const Vec3& d = frame.view.direction;
  const float dx = static_cast<float>(d.x), dy = static_cast<float>(d.y), dz = static_cast<float>(d.z);
  auto facing = [&](std::size_t f) { return normals_[f][0] * dx + normals_[f][1] * dy + normals_[f][2] * dz > 0; };
  if (options_.depth_test) {
    // Depth runs over [0, 1] across the view's 2r, one pixel across 2r/R: 1/R depth per pixel.
    mark_visible_vertices(frame, 1.5f / static_cast<float>(frame.resolution()), w.vertex_visible);
    for (std::size_t t = 0; t < scene_face_input_.size(); ++t) {
      const std::uint32_t f = input[t];
      if (seen[f] == frame_number || !facing(f)) continue;
      const Face& face = scene_faces_[t];
      if (w.vertex_visible[face[0]] || w.vertex_visible[face[1]] || w.vertex_visible[face[2]]) seen[f] = frame_number;
    }
  }
  // Neighbour fill reads only faces seen by pixels or the depth test, never ones it filled.
  for (std::size_t f = 0; f < mesh_.num_faces(); ++f) {
    bool set = seen[f] == frame_number;
    if (!set && options_.neighbour_fill && facing(f)) {
      for (std::uint32_t g : neighbours_[f]) {
        if (seen[g] == frame_number) {
          set = true;
          break;
        }
      }
    }
    if (set) row[face_patch[f] >> 6] |= std::uint64_t{1} << (face_patch[f] & 63);
  }
}

Bitfields BitfieldRecorder::finish() {
  for (std::size_t f = 0; f < options_.transparent.size(); ++f) {
    if (!options_.transparent[f]) continue;
    for (std::size_t c = 0; c < bits_.cameras; ++c) bits_.set(c, partition_.face_patch[f]);
  }
  return std::move(bits_);
}

Bitfields record_bitfields(const Mesh& mesh, const PatchPartition& partition, const CameraSet& cameras,
                           Renderer& renderer, const BitfieldOptions& options, RenderObserver* observer) {
  Mesh opaque;
  opaque.positions = mesh.positions;
  std::vector<std::uint32_t> scene_face_input;
  for (std::uint32_t f = 0; f < mesh.num_faces(); ++f) {
    if (!options.transparent.empty() && options.transparent[f]) continue;
    opaque.faces.push_back(mesh.faces[f]);
    scene_face_input.push_back(f);
  }
  // The views cover the whole mesh's bounding sphere, transparent faces included, so every
  // bitfield file of a mesh uses the same cameras.
  const BoundingBox box = bounding_box(mesh);
  const RenderScene scene = RenderScene::from_mesh(opaque, false, box.center(), view_radius(box));
  BitfieldRecorder recorder(mesh, scene, std::move(scene_face_input), partition, cameras.size(), options);
  renderer.render(scene, cameras, 0, cameras.size(), recorder, observer);
  return recorder.finish();
}

Bitfields patch_bitfields_from_faces(const Bitfields& faces, const PatchPartition& partition) {
  if (faces.units != partition.face_patch.size()) {
    throw UsageError("face bitfields of " + std::to_string(faces.units) + " faces for a partition of " +
                     std::to_string(partition.face_patch.size()));
  }
  Bitfields patches(partition.patch_count(), faces.cameras);
  for (std::size_t c = 0; c < faces.cameras; ++c) {
    std::uint64_t* out = patches.row(c);
    for_each_set_bit(faces.row(c), faces.words_per_row, [&](std::size_t f) {
      const std::uint32_t p = partition.face_patch[f];
      out[p >> 6] |= std::uint64_t{1} << (p & 63);
    });
  }
  return patches;
}

std::vector<std::uint8_t> read_face_list(const std::string& path, std::size_t faces) {
  std::ifstream in(path);
  if (!in) throw IoError(path, "cannot open the face list");
  std::vector<std::uint8_t> flags(faces, 0);
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    const std::size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string word;
    while (words >> word) {
      std::size_t index = 0, used = 0;
      try {
        index = std::stoull(word, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != word.size() || word[0] == '-') {
        throw IoError(path, "line " + std::to_string(number) + ": '" + word + "' is not a face index");
      }
      if (index >= faces) {
        throw IoError(path, "line " + std::to_string(number) + ": face " + word + " is out of range (the mesh has " +
                                std::to_string(faces) + " faces)");
      }
      flags[index] = 1;
    }
  }
  return flags;
}

BitfieldSet make_bitfield_set(const Mesh& mesh, const PatchPartition& partition, bool per_face, const CameraSet& cameras,
                              int resolution, const BitfieldOptions& options) {
  BitfieldSet set;
  set.mesh_hash = hash_mesh(mesh);
  set.faces = mesh.num_faces();
  set.per_face = per_face;
  set.neighbour_fill = options.neighbour_fill;
  set.depth_test = options.depth_test;
  for (const std::uint8_t flag : options.transparent) set.transparent_faces += flag;
  set.resolution = static_cast<std::uint32_t>(resolution);
  const BoundingBox box = bounding_box(mesh);
  set.center = box.center();
  set.radius = view_radius(box);
  set.cameras = cameras;
  if (!per_face) set.face_patch = partition.face_patch;
  return set;
}

}  // namespace visimp
