#include "visimp/io/mesh_io.h"

#include <gtest/gtest.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <sys/stat.h>  // mkfifo

#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/core/mesh_stats.h"

namespace visimp {
namespace {

// A mesh with everything the formats must keep: a non-manifold edge, a misoriented pair,
// a duplicate face, a zero-area face, an isolated vertex, and quality on both elements.
Mesh awkward_mesh() {
  Mesh m = test::grid(2);
  const VertexIndex top = VertexIndex(m.positions.size());
  m.positions.push_back({0.5, 0.5, 1.0});
  m.faces.push_back({0, 4, top});    // third face on edge 0-4: non-manifold
  m.faces.push_back(m.faces[0]);     // duplicate
  m.faces.push_back({0, 1, 2});      // collinear: zero area
  m.positions.push_back({7, 7, 7});  // isolated
  for (std::size_t v = 0; v < m.num_vertices(); ++v) m.vertex_quality.push_back(0.25f * float(v));
  for (std::size_t f = 0; f < m.num_faces(); ++f) m.face_quality.push_back(1.0f / float(f + 1));
  return m;
}

Mesh round_trip(const Mesh& m, Format format, bool binary) {
  std::stringstream buffer;
  WriteOptions w;
  w.binary = binary;
  write_mesh(m, buffer, format, w);
  return read_mesh_from_bytes(buffer.str(), format, "memory");
}

void expect_same_faces(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.num_faces(), b.num_faces());
  for (std::size_t f = 0; f < a.num_faces(); ++f) EXPECT_EQ(a.faces[f], b.faces[f]) << "face " << f;
}

TEST(MeshIo, PlyBinaryKeepsEverythingIncludingQuality) {
  const Mesh m = awkward_mesh();
  const Mesh r = round_trip(m, Format::ply, true);
  expect_same_faces(m, r);
  ASSERT_EQ(r.num_vertices(), m.num_vertices());
  for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(r.positions[v], m.positions[v]);
  EXPECT_EQ(r.vertex_quality, m.vertex_quality);
  EXPECT_EQ(r.face_quality, m.face_quality);
  const MeshStats s = analyze(r);
  EXPECT_EQ(s.non_manifold_edges, analyze(m).non_manifold_edges);
  EXPECT_EQ(s.duplicate_faces, 1u);
  EXPECT_EQ(s.isolated_vertices, 1u);
}

TEST(MeshIo, PlyAsciiKeepsEverythingIncludingQuality) {
  const Mesh m = awkward_mesh();
  const Mesh r = round_trip(m, Format::ply, false);
  expect_same_faces(m, r);
  EXPECT_EQ(r.vertex_quality, m.vertex_quality);
  EXPECT_EQ(r.face_quality, m.face_quality);
}

TEST(MeshIo, ObjAndOffKeepFacesAndIsolatedVertices) {
  const Mesh m = awkward_mesh();
  for (Format f : {Format::obj, Format::off}) {
    const Mesh r = round_trip(m, f, true);
    expect_same_faces(m, r);
    EXPECT_EQ(r.num_vertices(), m.num_vertices());
    for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(r.positions[v], m.positions[v]);
  }
}

TEST(MeshIo, StlKeepsEveryFaceInBothEncodings) {
  Mesh m = awkward_mesh();
  m.positions.pop_back();  // STL cannot hold an isolated vertex
  m.vertex_quality.clear();
  m.face_quality.clear();
  for (bool binary : {true, false}) {
    const Mesh r = round_trip(m, Format::stl, binary);
    // Welding exact duplicates recovers the shared vertices (numbered by first use), so every
    // face comes back with the same corner positions.
    ASSERT_EQ(r.num_faces(), m.num_faces());
    EXPECT_EQ(r.num_vertices(), m.num_vertices());
    for (std::size_t f = 0; f < m.num_faces(); ++f)
      for (int k = 0; k < 3; ++k) EXPECT_EQ(r.positions[r.faces[f][k]], m.positions[m.faces[f][k]]);
  }
}

TEST(MeshIo, PlyWritesDoubleOnlyWhenFloatWouldLosePrecision) {
  Mesh m = test::grid(1);
  std::stringstream plain;
  write_mesh(m, plain, Format::ply);
  EXPECT_NE(plain.str().find("property float x"), std::string::npos);
  // A 1 mm square at x = 1e7 mm: float's spacing there is 1 mm, the whole size of the mesh.
  for (Vec3& p : m.positions) p = Vec3{1e7 + 1e-3 * p.x, 1e-3 * p.y, 0};
  std::stringstream far;
  write_mesh(m, far, Format::ply);
  EXPECT_NE(far.str().find("property double x"), std::string::npos);
  const Mesh r = read_mesh_from_bytes(far.str(), Format::ply, "far.ply");
  for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(r.positions[v], m.positions[v]);
}

// Past the 1 MiB block the binary writer fills and flushes: every vertex, face and quality
// comes back, also the `source_face` column after the indices.
TEST(MeshIo, PlyBinaryRoundTripOfSeveralMegabytes) {
  Mesh m = test::grid(400);  // 320,000 faces: ~4 MB of faces, ~2 MB of vertices
  for (std::size_t v = 0; v < m.num_vertices(); ++v) m.vertex_quality.push_back(float(v % 977) / 977.0f);
  for (std::size_t f = 0; f < m.num_faces(); ++f) m.face_quality.push_back(float(f % 613) / 613.0f);
  std::vector<std::uint32_t> source(m.num_faces());
  for (std::size_t f = 0; f < source.size(); ++f) source[f] = std::uint32_t(3 * f + 1);
  for (const bool with_quality : {true, false}) {
    Mesh written = m;
    if (!with_quality) written.vertex_quality.clear(), written.face_quality.clear();
    std::stringstream buffer;
    WriteOptions w;
    w.source_face = &source;
    write_mesh(written, buffer, Format::ply, w);
    ASSERT_GT(buffer.str().size(), std::size_t(5) << 20);
    const Mesh r = read_mesh_from_bytes(buffer.str(), Format::ply, "big.ply");
    expect_same_faces(written, r);
    ASSERT_EQ(r.num_vertices(), written.num_vertices());
    for (std::size_t v = 0; v < written.num_vertices(); ++v) ASSERT_EQ(r.positions[v], written.positions[v]) << v;
    EXPECT_EQ(r.vertex_quality, written.vertex_quality);
    EXPECT_EQ(r.face_quality, written.face_quality);
  }
}

// The layouts read by the quickest paths, with what makes them unusual: vertex properties
// around and between x, y, z and quality (floats, uchar colours, a double), and index lists of
// 3, 4 and 5 entries as uint (fans, as in the general reader); then the same file with a double
// quality, which takes the general binary path, must read the same.
TEST(MeshIo, ReadsBinaryPlyVerticesWithOtherPropertiesAndPolygonFaces) {
  const auto file = [](bool double_quality) {
    std::string bytes = "ply\nformat binary_little_endian 1.0\nelement vertex 6\n"
                        "property uchar red\nproperty float x\nproperty double weight\nproperty float y\n"
                        "property float z\nproperty " +
                        std::string(double_quality ? "double" : "float") +
                        " quality\nproperty uchar green\nelement face 3\n"
                        "property list uchar uint vertex_indices\nend_header\n";
    const auto put = [&bytes](const auto& value) { bytes.append(reinterpret_cast<const char*>(&value), sizeof value); };
    for (int v = 0; v < 6; ++v) {
      put(std::uint8_t(200 + v));
      put(float(v) + 0.5f);
      put(double(-v));
      put(float(2 * v));
      put(float(-3 * v) - 0.25f);
      if (double_quality)
        put(double(v) / 8);
      else
        put(float(v) / 8);
      put(std::uint8_t(7));
    }
    const std::vector<std::vector<std::uint32_t>> polygons = {{0, 1, 2}, {1, 2, 3, 4}, {5, 4, 3, 2, 1}};
    for (const auto& polygon : polygons) {
      put(std::uint8_t(polygon.size()));
      for (std::uint32_t i : polygon) put(i);
    }
    return bytes;
  };
  for (const bool double_quality : {false, true}) {
    const Mesh m = read_mesh_from_bytes(file(double_quality), Format::ply, "layout.ply");
    ASSERT_EQ(m.num_vertices(), 6u);
    for (int v = 0; v < 6; ++v) {
      EXPECT_EQ(m.positions[v], (Vec3{v + 0.5, 2.0 * v, -3.0 * v - 0.25})) << v;
      EXPECT_EQ(m.vertex_quality[v], float(v) / 8) << v;
    }
    const std::vector<Face> fans = {{0, 1, 2}, {1, 2, 3}, {1, 3, 4}, {5, 4, 3}, {5, 3, 2}, {5, 2, 1}};
    ASSERT_EQ(m.faces, fans) << (double_quality ? "general path" : "float path");
  }
}

TEST(MeshIo, ReadsBigEndianPlyWithExtraPropertiesAndElements) {
  // Header: doubles, an extra uchar per vertex, an int-indexed list, a trailing element.
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\ncomment test\nelement vertex 3\n"
      "property double x\nproperty double y\nproperty double z\nproperty uchar red\n"
      "element face 1\nproperty list uchar uint vertex_indices\nproperty float quality\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  auto put_be = [&bytes](const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    for (std::size_t i = 0; i < n; ++i) bytes.push_back(c[n - 1 - i]);
  };
  const double coords[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}};
  for (const auto& v : coords) {
    for (double c : v) put_be(&c, 8);
    bytes.push_back(char(200));
  }
  bytes.push_back(3);
  for (std::uint32_t i : {0u, 1u, 2u}) put_be(&i, 4);
  const float q = 0.5f;
  put_be(&q, 4);
  for (std::int32_t i : {0, 1}) put_be(&i, 4);
  const Mesh m = read_mesh_from_bytes(bytes, Format::ply, "be.ply");
  ASSERT_EQ(m.num_vertices(), 3u);
  EXPECT_EQ(m.positions[2], (Vec3{0, 2, 0}));
  ASSERT_EQ(m.num_faces(), 1u);
  EXPECT_EQ(m.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(m.face_quality, std::vector<float>{0.5f});
}

TEST(MeshIo, ObjNegativeIndicesSlashFormsAndPolygons) {
  const std::string obj =
      "# square as one quad, then a triangle by relative indices\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "f 1/1/1 2/1/1 3//1 4\n"
      "v 2 0 0\n"
      "f -4 -1 -3\n";
  const Mesh m = read_mesh_from_bytes(obj, Format::obj, "t.obj");
  ASSERT_EQ(m.num_faces(), 3u);  // the quad is fanned into 2 triangles
  EXPECT_EQ(m.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(m.faces[1], (Face{0, 2, 3}));
  EXPECT_EQ(m.faces[2], (Face{1, 4, 2}));
}

TEST(MeshIo, OffWithColoursAndComments) {
  const std::string off =
      "COFF\n# comment\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 1 2 3 4\n1 1 0 1 2 3 4\n0 1 0 1 2 3 4\n"
      "4 0 1 2 3 255 0 0\n3 0 1 3\n";
  const Mesh m = read_mesh_from_bytes(off, Format::off, "t.off");
  EXPECT_EQ(m.num_faces(), 3u);
}

TEST(MeshIo, RealMeshesRoundTripThroughEveryFormat) {
  const Mesh m = read_mesh(test::bundled_mesh("bunny.ply"));
  EXPECT_EQ(m.num_faces(), 3674u);  // meshes/SOURCES.md
  for (Format f : {Format::ply, Format::obj, Format::off, Format::stl}) {
    const Mesh r = round_trip(m, f, true);
    EXPECT_EQ(r.num_faces(), m.num_faces()) << format_name(f);
  }
}

TEST(MeshIo, WriteIsAtomicAndLeavesNoTemporaryFiles) {
  const test::TempDir temp("atomic");
  const std::string& dir = temp.path();
  const std::string path = dir + "/out.ply";
  write_mesh(test::grid(2), path);
  write_mesh(test::grid(3), path);  // replaces the file in one rename
  EXPECT_EQ(read_mesh(path).num_faces(), 18u);
  std::size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);
}

// read_mesh reads a file straight into one array (huge-page backed from 256 KiB, mapped
// whole below 4 MiB): every size class gives back what was written, and a path with no size
// (a named pipe) is read to its end through the same reader.
TEST(MeshIo, ReadsFilesOfEverySizeAndANamedPipe) {
  const test::TempDir temp("sizes");
  for (int n : {3, 160, 520}) {  // binary PLY of ~2 KB, ~1 MB and ~10 MB
    const Mesh m = test::grid(n);
    const std::string path = temp.path() + "/grid" + std::to_string(n) + ".ply";
    write_mesh(m, path);
    const Mesh r = read_mesh(path);
    expect_same_faces(m, r);
    EXPECT_EQ(r.positions, m.positions) << n;
  }
  // ~10 MB through the pipe: its array grows through every size class on the way.
  const std::string fifo = temp.path() + "/pipe.ply";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  std::stringstream encoded;
  write_mesh(test::grid(520), encoded, Format::ply, WriteOptions{});
  const std::string bytes = encoded.str();
  ASSERT_GT(bytes.size(), std::size_t(8) << 20);
  // A read that fails closes the pipe under the writer: EPIPE for it, not a SIGPIPE for the run.
  const auto old_sigpipe = std::signal(SIGPIPE, SIG_IGN);
  std::thread writer([&] { std::ofstream(fifo, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size())); });
  Mesh r;
  try {
    r = read_mesh(fifo);
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what();
  }
  writer.join();  // also after a failed read: a joinable thread's destructor would abort the run
  std::signal(SIGPIPE, old_sigpipe);
  expect_same_faces(test::grid(520), r);
}

TEST(MeshIo, FailedWriteKeepsTheOldFile) {
  const test::TempDir temp("failed_write");
  const std::string& dir = temp.path();
  const std::string path = dir + "/out.ply";
  write_mesh(test::grid(2), path);
  Mesh bad = test::grid(1);
  bad.faces.push_back({0, 1, 42});  // invalid: refused before anything is written
  EXPECT_THROW(write_mesh(bad, path), InvalidMeshError);
  EXPECT_EQ(read_mesh(path).num_faces(), 8u);
}

TEST(MeshIo, FormatFromPath) {
  EXPECT_EQ(format_from_path("a/b.PLY"), Format::ply);
  EXPECT_EQ(format_from_path("x.stl"), Format::stl);
  EXPECT_EQ(format_from_path("x.DAE"), Format::collada);
  EXPECT_EQ(format_from_path("x.glb"), Format::glb);
  EXPECT_THROW(format_from_path("x.blend"), UsageError);
  EXPECT_THROW(format_from_path("noext"), UsageError);
}

TEST(DetectFormat, EveryWriterIsRecognisedAndJunkIsNot) {
  const Mesh m = test::icosphere(1);
  for (const Format f : {Format::ply, Format::obj, Format::off, Format::stl}) {
    for (const bool binary : {true, false}) {
      std::ostringstream out;
      WriteOptions options;
      options.binary = binary;
      write_mesh(m, out, f, options);
      EXPECT_EQ(detect_format(out.str()), f) << format_name(f) << (binary ? " binary" : " ascii");
    }
  }
  // A binary STL whose header starts with "solid" is still binary (its size says so).
  std::string stl(80, ' ');
  stl.replace(0, 5, "solid");
  const std::uint32_t one = 1;
  stl.append(reinterpret_cast<const char*>(&one), 4).append(50, '\0');
  EXPECT_EQ(detect_format(stl), Format::stl);
  EXPECT_EQ(detect_format("# a comment\n\nv 0 0 0\n"), Format::obj);
  EXPECT_EQ(detect_format("# comment\nCOFF\n3 1 0\n"), Format::off);
  for (const char* junk : {"", "hello\n", "plyx\n", "3 1 0\n", "solid and nothing else\n", "OFFICE\n"}) {
    EXPECT_FALSE(detect_format(junk).has_value()) << junk;
  }
}

}  // namespace
}  // namespace visimp
