#include "visimp/io/scene_formats.h"

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include "exact_welder.h"
#include "isolated_child.h"
#include "visimp/core/errors.h"

namespace visimp {
namespace {

// Triangulate polygons and split primitive types so points and lines can be dropped;
// validate what the importer built (index ranges, counts) before we read it. No vertex
// joining here: assimp's compares normals and UVs too, we weld positions ourselves.
constexpr unsigned kImportFlags = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;

// Deeper than this is a malformed (or hostile) file, not a scene: no stack grows without bound.
constexpr int kMaxNodeDepth = 1000;

void configure(Assimp::Importer& importer) {
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  importer.SetPropertyBool(AI_CONFIG_IMPORT_NO_SKELETON_MESHES, true);
}

// assimp's messages may span lines; ours are one line.
std::string one_line(std::string text) {
  for (char& c : text)
    if (c == '\n' || c == '\r') c = ' ';
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text.empty() ? std::string("unknown error") : text;
}

using Matrix = std::array<double, 16>;  // row-major, as aiMatrix4x4 (a1 a2 a3 a4 / b1 ...)

Matrix to_double(const aiMatrix4x4& m) {
  return {m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4};
}

Matrix multiply(const Matrix& a, const Matrix& b) {
  Matrix c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[std::size_t(4 * i + k)] * b[std::size_t(4 * k + j)];
      c[std::size_t(4 * i + j)] = s;
    }
  return c;
}

Vec3 transform_point(const Matrix& m, const aiVector3D& v) {
  const double x = v.x, y = v.y, z = v.z;
  const double w = m[12] * x + m[13] * y + m[14] * z + m[15];
  Vec3 p{m[0] * x + m[1] * y + m[2] * z + m[3], m[4] * x + m[5] * y + m[6] * z + m[7],
         m[8] * x + m[9] * y + m[10] * z + m[11]};
  if (w != 1.0 && w != 0.0) p = p / w;  // affine in practice; honour a projective row if present
  return p;
}

// assimp reports some losses only as log warnings ("Some faces had out-of-range indices. Those
// faces were dropped."). Nothing a user gave us may vanish silently, so we listen to its log
// while importing and turn those warnings into errors. The log is process-global; imports run
// in a single-threaded child process (below), so no lock is needed.
class WarningCapture : public Assimp::LogStream {
 public:
  void write(const char* message) override {
    std::string text = one_line(message);
    if (const auto colon = text.find(": "); colon != std::string::npos && colon < 16) text.erase(0, colon + 2);
    warnings.push_back(std::move(text));
  }
  std::vector<std::string> warnings;
};

bool reports_lost_geometry(const std::string& warning) {
  return warning.find("dropped") != std::string::npos || warning.find("ignored") != std::string::npos ||
         warning.find("skipped") != std::string::npos;
}

// Runs one import with assimp's log captured, then rejects a scene that lost faces on the way.
template <class Import>
const aiScene* import_listening(Import&& run, const std::string& name) {
  Assimp::DefaultLogger::create(nullptr, Assimp::Logger::NORMAL, 0);
  auto capture = std::make_unique<WarningCapture>();
  Assimp::DefaultLogger::get()->attachStream(capture.get(), Assimp::Logger::Warn | Assimp::Logger::Err);
  const aiScene* scene = run();
  Assimp::DefaultLogger::get()->detachStream(capture.get(), Assimp::Logger::Warn | Assimp::Logger::Err);
  Assimp::DefaultLogger::kill();
  if (scene != nullptr)
    for (const std::string& warning : capture->warnings)
      if (reports_lost_geometry(warning)) throw IoError(name, "assimp lost part of it: " + warning);
  return scene;
}

Mesh flatten(const aiScene& scene, const std::string& name, FaceGroups* groups) {
  if (scene.mRootNode == nullptr) throw IoError(name, "assimp: the scene has no root node");
  Mesh mesh;
  FaceGroups found;
  std::size_t dropped_polygons = 0;
  struct Pending {
    const aiNode* node;
    Matrix parent;
    int depth;
  };
  const Matrix identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  std::vector<Pending> stack{{scene.mRootNode, identity, 0}};
  while (!stack.empty()) {
    const Pending item = stack.back();
    stack.pop_back();
    const aiNode& node = *item.node;
    if (item.depth > kMaxNodeDepth)
      throw IoError(name, "assimp: scene nodes nest deeper than " + std::to_string(kMaxNodeDepth));
    const Matrix transform = multiply(item.parent, to_double(node.mTransformation));
    if (node.mNumMeshes > 0) {
      const auto group = static_cast<std::uint32_t>(found.names.size());
      found.names.emplace_back(node.mName.C_Str());
      detail::ExactWelder welder(mesh);  // per node: one part's seams close, parts stay apart
      for (unsigned i = 0; i < node.mNumMeshes; ++i) {
        const unsigned index = node.mMeshes[i];
        if (index >= scene.mNumMeshes || scene.mMeshes[index] == nullptr)
          throw IoError(name, "assimp: node '" + std::string(node.mName.C_Str()) + "' names missing mesh " +
                                  std::to_string(index));
        const aiMesh& part = *scene.mMeshes[index];
        for (unsigned f = 0; f < part.mNumFaces; ++f) {
          const aiFace& face = part.mFaces[f];
          if (face.mNumIndices != 3) {
            ++dropped_polygons;  // points and lines (SortByPType keeps none, but be sure)
            continue;
          }
          Face out;
          for (unsigned k = 0; k < 3; ++k) {
            const unsigned v = face.mIndices[k];
            if (v >= part.mNumVertices)
              throw IoError(name, "assimp: mesh " + std::to_string(index) + " face " + std::to_string(f) +
                                      " has vertex index " + std::to_string(v) + " >= " +
                                      std::to_string(part.mNumVertices) + " vertices");
            const Vec3 p = transform_point(transform, part.mVertices[v]);
            if (!is_finite(p))
              throw IoError(name, "assimp: mesh " + std::to_string(index) + " vertex " + std::to_string(v) +
                                      " is not finite (after its node's transform)");
            if (mesh.positions.size() >= std::numeric_limits<VertexIndex>::max())
              throw IoError(name, "assimp: more vertices than 32-bit indices can address");
            out[k] = welder.add(p);
          }
          mesh.faces.push_back(out);
          found.face_group.push_back(group);
        }
      }
    }
    for (unsigned c = node.mNumChildren; c-- > 0;)  // reversed: children pop in document order
      if (node.mChildren[c] != nullptr) stack.push_back({node.mChildren[c], transform, item.depth + 1});
  }
  if (mesh.faces.empty())
    throw IoError(name, "assimp: the scene has no triangles (" + std::to_string(scene.mNumMeshes) + " meshes" +
                            (dropped_polygons ? ", only points and lines" : "") + ")");
  if (groups != nullptr) *groups = std::move(found);
  return mesh;
}

Mesh imported(Assimp::Importer& importer, const aiScene* scene, Format format, const std::string& name,
              FaceGroups* groups) {
  if (scene == nullptr) {
    const std::string why = one_line(importer.GetErrorString());
    if (why == "No meshes remaining")  // what assimp says once points and lines are removed
      throw IoError(name, "the scene has no triangles (only points or lines)");
    throw IoError(name, std::string("assimp cannot read it as ") + format_name(format) + ": " + why);
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0 && scene->mNumMeshes == 0)
    throw IoError(name, "assimp: the scene is incomplete and has no meshes");
  return flatten(*scene, name, groups);
}

// The child's answer: the flattened mesh and its groups, as raw little-endian arrays.
template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

std::string encode(const Mesh& mesh, const FaceGroups& groups) {
  std::string out;
  put(out, std::uint64_t(mesh.positions.size()));
  put(out, std::uint64_t(mesh.faces.size()));
  put(out, std::uint64_t(groups.names.size()));
  out.append(reinterpret_cast<const char*>(mesh.positions.data()), mesh.positions.size() * sizeof(Vec3));
  out.append(reinterpret_cast<const char*>(mesh.faces.data()), mesh.faces.size() * sizeof(Face));
  out.append(reinterpret_cast<const char*>(groups.face_group.data()), groups.face_group.size() * sizeof(std::uint32_t));
  for (const std::string& name : groups.names) {
    put(out, std::uint64_t(name.size()));
    out += name;
  }
  return out;
}

class Decoder {
 public:
  explicit Decoder(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  void take(T* out, std::uint64_t count) {
    if (count > (bytes_.size() - at_) / sizeof(T)) throw detail::ChildFailure("sent a truncated mesh");
    std::memcpy(static_cast<void*>(out), bytes_.data() + at_, count * sizeof(T));
    at_ += count * sizeof(T);
  }
  std::uint64_t count() {
    std::uint64_t n = 0;
    take(&n, 1);
    return n;
  }
  bool done() const { return at_ == bytes_.size(); }

 private:
  const std::string& bytes_;
  std::size_t at_ = 0;
};

Mesh decode(const std::string& bytes, FaceGroups& groups) {
  Decoder in(bytes);
  const std::uint64_t vertices = in.count(), faces = in.count(), names = in.count();
  if (vertices > bytes.size() / sizeof(Vec3) || faces > bytes.size() / sizeof(Face) || names > bytes.size())
    throw detail::ChildFailure("sent impossible counts");
  Mesh mesh;
  mesh.positions.resize(vertices);
  mesh.faces.resize(faces);
  groups.face_group.resize(faces);
  groups.names.resize(names);
  in.take(mesh.positions.data(), vertices);
  in.take(mesh.faces.data(), faces);
  in.take(groups.face_group.data(), faces);
  for (std::string& name : groups.names) {
    const std::uint64_t size = in.count();
    if (size > bytes.size()) throw detail::ChildFailure("sent an impossible name");
    name.resize(size);
    in.take(name.data(), size);
  }
  if (!in.done()) throw detail::ChildFailure("sent trailing bytes");
  return mesh;
}

// Imports in a child process: Debian's assimp is not hardened (fuzzing finds its crashes,
// runaway allocations and leaks in seconds), and a malformed file must cost the caller an
// IoError, not the process. Memory: the child may map 2 GiB plus 64 bytes per input byte
// beyond what the parent holds; time: 10 CPU minutes plus one per 10 MB.
template <class Import>
Mesh import_isolated(Import&& import_and_flatten, std::size_t input_bytes, const std::string& name,
                     FaceGroups* groups) {
  detail::ChildLimits limits;
  limits.extra_memory = (std::size_t(2) << 30) + 64 * input_bytes;
  limits.cpu_seconds = 600 + unsigned(input_bytes / 10'000'000 * 60);
  std::string answer;
  try {
    answer = detail::run_in_child(
        [&] {
          FaceGroups found;
          const Mesh mesh = import_and_flatten(found);
          return encode(mesh, found);
        },
        limits);
  } catch (const detail::ChildFailure& failure) {
    const std::string why = failure.what();
    const std::string prefix = name + ": ";
    if (why.rfind(prefix, 0) == 0) throw IoError(name, why.substr(prefix.size()));  // our IoError, from the child
    throw IoError(name, "assimp " + one_line(why));
  }
  FaceGroups found;
  try {
    Mesh mesh = decode(answer, found);
    if (groups != nullptr) *groups = std::move(found);
    return mesh;
  } catch (const detail::ChildFailure& failure) {
    throw IoError(name, std::string("the import process ") + failure.what());
  }
}

}  // namespace

bool is_scene_format(Format format) {
  switch (format) {
    case Format::gltf:
    case Format::glb:
    case Format::threemf:
    case Format::collada:
    case Format::fbx:
    case Format::x3d:
      return true;
    default:
      return false;
  }
}

Mesh read_scene_file(const std::string& path, Format format, FaceGroups* groups) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return import_isolated(
      [&](FaceGroups& found) {
        Assimp::Importer importer;
        configure(importer);
        const aiScene* scene = import_listening([&] { return importer.ReadFile(path, kImportFlags); }, path);
        return imported(importer, scene, format, path, &found);
      },
      ec ? 0 : std::size_t(size), path, groups);
}

Mesh read_scene_bytes(std::string_view bytes, Format format, const std::string& name, FaceGroups* groups) {
  if (bytes.empty()) throw IoError(name, "file is empty");
  return import_isolated(
      [&](FaceGroups& found) {
        Assimp::Importer importer;
        configure(importer);
        const aiScene* scene = import_listening(
            [&] { return importer.ReadFileFromMemory(bytes.data(), bytes.size(), kImportFlags, format_name(format)); },
            name);
        return imported(importer, scene, format, name, &found);
      },
      bytes.size(), name, groups);
}

}  // namespace visimp
