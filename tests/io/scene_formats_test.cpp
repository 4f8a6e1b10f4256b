// The scene formats read through assimp (glTF, GLB, 3MF, COLLADA, FBX, X3D): counts and welds on
// the sample scenes Debian ships in assimp-testmodels, node transforms and groups on a glTF built
// here with known answers, clear errors where assimp would drop geometry, and our own writers'
// files read back by assimp (an independent reader) face for face.
#include "visimp/io/scene_formats.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

namespace fs = std::filesystem;

// Debian's assimp-testmodels (installed by .ci/install-deps).
const std::string kModels = "/usr/share/assimp/models/";

class SceneFormats : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!fs::exists(kModels + "glTF2"))
      GTEST_SKIP() << kModels << " is missing: install assimp-testmodels (.ci/install-deps does)";
  }
};

std::string expect_io_error(const std::string& path) {
  try {
    read_mesh(path);
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << "the error names the file: " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    return what;
  }
  ADD_FAILURE() << path << " was read without an error";
  return {};
}

// Every stored copy of the textured box (external .bin, embedded base64, binary) is the same
// closed cube: 24 assimp vertices (split by normal and UV) weld back to 8.
TEST_F(SceneFormats, GltfBoxInEveryEncodingWeldsToEightVertices) {
  const Mesh reference = read_mesh(kModels + "glTF2/BoxTextured-glTF/BoxTextured.gltf");
  EXPECT_EQ(reference.num_vertices(), 8u);
  EXPECT_EQ(reference.num_faces(), 12u);
  const MeshStats stats = analyze(reference);
  EXPECT_TRUE(stats.closed_manifold());
  EXPECT_EQ(stats.misoriented_edges, 0u);
  EXPECT_NEAR(stats.area, 6.0, 1e-9);
  for (const char* other : {"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf",
                            "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"}) {
    const Mesh m = read_mesh(kModels + other);
    EXPECT_EQ(m.positions, reference.positions) << other;
    EXPECT_EQ(m.faces, reference.faces) << other;
  }
}

TEST_F(SceneFormats, SampleScenesInEachFormatHaveTheirKnownCounts) {
  struct Known {
    const char* file;
    Format format;
    std::size_t vertices, faces;
    bool closed;
  };
  for (const Known& k : {Known{"3MF/box.3mf", Format::threemf, 8, 12, true},
                         Known{"Collada/duck.dae", Format::collada, 2108, 4212, true},
                         Known{"FBX/box.fbx", Format::fbx, 8, 12, true},
                         Known{"X3D/ComputerKeyboard.x3d", Format::x3d, 58, 100, true},
                         Known{"glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", Format::glb, 60041, 121496,
                               false}}) {
    SCOPED_TRACE(k.file);
    EXPECT_EQ(format_from_path(k.file), k.format);
    FaceGroups groups;
    const Mesh m = read_mesh_with_groups(kModels + k.file, groups);
    EXPECT_EQ(m.num_vertices(), k.vertices);
    EXPECT_EQ(m.num_faces(), k.faces);
    EXPECT_EQ(analyze(m).closed_manifold(), k.closed);
    ASSERT_EQ(groups.face_group.size(), m.num_faces());
    for (const std::uint32_t g : groups.face_group) ASSERT_LT(g, groups.names.size());
  }
}

// The engine is 86 separate parts, each its own node: groups follow the nodes, not one blob.
TEST_F(SceneFormats, EachNodeWithMeshesIsOneGroup) {
  FaceGroups groups;
  const Mesh m = read_mesh_with_groups(kModels + "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", groups);
  EXPECT_GT(groups.names.size(), 20u);
  EXPECT_EQ(std::set<std::uint32_t>(groups.face_group.begin(), groups.face_group.end()).size(), groups.names.size())
      << "every group holds faces";
  // Faces of one group are contiguous (a node's meshes are read together).
  for (std::size_t f = 1; f < m.num_faces(); ++f)
    ASSERT_LE(groups.face_group[f - 1], groups.face_group[f]) << "face " << f;
}

// COLLADA instance_node: one teapot geometry placed by several nodes. Each placement is a group
// with the same face count, and the placements do not coincide (their transforms were applied).
TEST_F(SceneFormats, InstancedNodesArePlacedByTheirTransforms) {
  FaceGroups groups;
  const Mesh m = read_mesh_with_groups(kModels + "Collada/teapot_instancenodes.DAE", groups);
  ASSERT_GE(groups.names.size(), 2u);
  std::vector<std::size_t> faces(groups.names.size(), 0);
  std::vector<Vec3> centroid(groups.names.size(), Vec3{0, 0, 0});
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const std::uint32_t g = groups.face_group[f];
    ++faces[g];
    for (const VertexIndex v : m.faces[f]) centroid[g] = centroid[g] + m.positions[v];
  }
  for (std::size_t g = 0; g < faces.size(); ++g) {
    EXPECT_EQ(faces[g], faces[0]) << "group " << g;
    centroid[g] = centroid[g] / double(3 * faces[g]);
  }
  for (std::size_t a = 0; a < faces.size(); ++a)
    for (std::size_t b = a + 1; b < faces.size(); ++b)
      EXPECT_GT(norm(centroid[a] - centroid[b]), 1e-3) << "groups " << a << " and " << b << " coincide";
}

// A glTF written here: one triangle, placed by a node under a translated parent (the transforms
// compose) and by a node of its own (identity); a third node holds no mesh. Known positions.
const char* kTwoPlacementsGltf = R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": [0, 2, 3]}],
  "nodes": [
    {"name": "parent", "translation": [10, 0, 0], "children": [1]},
    {"name": "moved", "translation": [0, 5, 0], "scale": [2, 2, 2], "mesh": 0},
    {"name": "still", "mesh": 0},
    {"name": "empty"}
  ],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 4}]}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}],
  "bufferViews": [{"buffer": 0, "byteLength": 36}],
  "buffers": [{"byteLength": 36,
               "uri": "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]
})";

TEST(SceneFormatsBuilt, NodeTransformsComposeAndGroupsFollowNodes) {
  FaceGroups groups;
  const Mesh m = read_scene_bytes(kTwoPlacementsGltf, Format::gltf, "built.gltf", &groups);
  ASSERT_EQ(m.num_faces(), 2u);
  ASSERT_EQ(m.num_vertices(), 6u) << "nodes are not welded to one another";
  EXPECT_EQ(groups.names, (std::vector<std::string>{"moved", "still"}));
  EXPECT_EQ(groups.face_group, (std::vector<std::uint32_t>{0, 1}));
  // moved: parent translation (10,0,0) after its own scale 2 and translation (0,5,0).
  const std::vector<Vec3> expected{{10, 5, 0}, {12, 5, 0}, {10, 7, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  for (std::size_t i = 0; i < 2; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.positions[m.faces[i][k]], expected[3 * i + std::size_t(k)]);
  // Through read_mesh too, from a file with no help from the extension (the content decides).
  const test::TempDir temp("built_gltf");
  const std::string path = temp.path() + "/scene";
  std::ofstream(path) << kTwoPlacementsGltf;
  FormatChoice choice;
  const Mesh again = read_mesh(path, std::nullopt, &choice);
  EXPECT_EQ(choice.format, Format::gltf);
  EXPECT_TRUE(choice.detected);
  EXPECT_EQ(again.positions, m.positions);
}

TEST(SceneFormatsBuilt, EmptyAndGarbageBytesAreOneLineErrors) {
  EXPECT_THROW(read_scene_bytes("", Format::glb, "empty.glb"), IoError);
  for (const Format f : {Format::gltf, Format::glb, Format::threemf, Format::collada, Format::fbx, Format::x3d}) {
    SCOPED_TRACE(format_name(f));
    try {
      read_scene_bytes("this is not a scene at all\n", f, "junk");
      ADD_FAILURE() << "junk was read";
    } catch (const IoError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
      EXPECT_EQ(std::string(e.what()).rfind("junk", 0), 0u) << e.what();
    }
  }
}

// Where assimp would quietly drop faces or vertices, or cannot build the scene, the user gets
// an error naming the file, not a mesh with parts missing.
TEST_F(SceneFormats, BrokenScenesAreClearErrorsNotSilentLosses) {
  EXPECT_NE(expect_io_error(kModels + "glTF2/IndexOutOfRange/IndexOutOfRange.gltf").find("dropped"),
            std::string::npos);
  EXPECT_NE(expect_io_error(kModels + "glTF2/IncorrectVertexArrays/Cube.gltf").find("dropped"), std::string::npos);
  EXPECT_NE(expect_io_error(kModels + "glTF2/MissingBin/BoxTextured.gltf").find("BoxTextured0.bin"),
            std::string::npos);
  EXPECT_NE(expect_io_error(kModels + "glTF2/RecursiveNodes/RecursiveNodes.gltf").find("recursive"),
            std::string::npos);
  EXPECT_NE(expect_io_error(kModels + "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb").find("not finite"),
            std::string::npos);
  EXPECT_NE(expect_io_error(kModels + "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf")
                .find("no triangles"),
            std::string::npos);
  EXPECT_NE(expect_io_error(kModels + "Collada/lights.dae").find("no meshes"), std::string::npos);
}

// A skin whose inverseBindMatrices key is misspelt (a fuzzer's find) crashes Debian's assimp
// 5.2 with a null dereference. The import runs in a child process, so it is an error naming the
// file, and the next read works.
TEST_F(SceneFormats, AnAssimpCrashIsAnErrorAndNotOurs) {
  std::string skin = read_file_bytes(kModels + "glTF2/simple_skin/simple_skin.gltf");
  const std::size_t at = skin.find("inverseBindMatrices");
  ASSERT_NE(at, std::string::npos);
  skin.replace(at, 19, "inverseBindMat2ices");
  try {
    const Mesh m = read_scene_bytes(skin, Format::gltf, "skin.gltf");  // an assimp that survives it
    EXPECT_GT(m.num_faces(), 0u);
  } catch (const IoError& e) {
    EXPECT_EQ(e.file(), "skin.gltf");
    EXPECT_EQ(e.problem().rfind("assimp", 0), 0u) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_mesh(kModels + "3MF/box.3mf").num_faces(), 12u);
}

TEST_F(SceneFormats, ContentAnnouncesBinaryGltfFbxColladaAndX3d) {
  for (const auto& [file, format] : std::vector<std::pair<std::string, Format>>{
           {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", Format::glb},
           {"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", Format::gltf},
           {"FBX/spider.fbx", Format::fbx},
           {"Collada/duck.dae", Format::collada},
           {"X3D/ComputerKeyboard.x3d", Format::x3d}}) {
    const auto detected = detect_format(read_file_bytes(kModels + file));
    ASSERT_TRUE(detected.has_value()) << file;
    EXPECT_EQ(*detected, format) << file;
  }
  // The same bytes from memory (stdin) as from the file.
  const std::string glb = kModels + "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
  EXPECT_EQ(read_mesh_from_bytes(read_file_bytes(glb), Format::glb, "<stdin>").positions, read_mesh(glb).positions);
}

TEST(SceneFormatsBuilt, WritingAReadOnlyFormatIsRefusedAndWritesNothing) {
  const test::TempDir temp("read_only_formats");
  const Mesh cube = test::subdivided_cube(1);
  for (const char* ext : {"gltf", "glb", "3mf", "dae", "fbx", "x3d"}) {
    const std::string path = temp.path() + "/out." + ext;
    EXPECT_FALSE(is_writable(format_from_path(path))) << ext;
    EXPECT_THROW(write_mesh(cube, path), UsageError) << ext;
    EXPECT_FALSE(fs::exists(path)) << ext;
  }
  EXPECT_TRUE(fs::is_empty(temp.path()));
}

// Our writers' files, read by assimp (an independent reader): every triangle comes back with
// the same corners (as float, what OBJ/STL/float PLY hold), in the same order.
TEST(SceneFormatsBuilt, AssimpReadsWhatOurWritersWrite) {
  const test::TempDir temp("assimp_reads_ours");
  const Mesh mesh = read_mesh(test::bundled_mesh("teapot.ply"));
  for (const auto& [ext, binary] : std::vector<std::pair<std::string, bool>>{
           {"ply", true}, {"ply", false}, {"obj", false}, {"off", false}, {"stl", true}, {"stl", false}}) {
    SCOPED_TRACE(ext + (binary ? " binary" : " ascii"));
    const std::string path = temp.path() + "/ours_" + (binary ? "b." : "a.") + ext;
    WriteOptions options;
    options.binary = binary;
    write_mesh(mesh, path, std::nullopt, options);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    std::size_t face = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
      const aiMesh& part = *scene->mMeshes[i];
      for (unsigned f = 0; f < part.mNumFaces; ++f, ++face) {
        ASSERT_LT(face, mesh.num_faces());
        ASSERT_EQ(part.mFaces[f].mNumIndices, 3u);
        for (unsigned k = 0; k < 3; ++k) {
          const aiVector3D& p = part.mVertices[part.mFaces[f].mIndices[k]];
          const Vec3& q = mesh.positions[mesh.faces[face][k]];
          ASSERT_EQ(p.x, float(q.x));
          ASSERT_EQ(p.y, float(q.y));
          ASSERT_EQ(p.z, float(q.z));
        }
      }
    }
    EXPECT_EQ(face, mesh.num_faces());
  }
}

}  // namespace
}  // namespace visimp
