// Every reader on broken input: a typed IoError naming the file and the problem, never a
// crash or an unbounded allocation.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

struct Case {
  const char* name;
  Format format;
  std::string bytes;
  const char* expected;  // a fragment of the message
};

std::string ply_header(const std::string& format, int nv, int nf) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(nv) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(nf) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::vector<Case> cases() {
  const std::string tri = "0 0 0\n1 0 0\n0 1 0\n";
  std::string truncated = ply_header("binary_little_endian", 3, 1);
  truncated += std::string(20, '\0');  // 36 bytes of vertices expected
  return {
      {"empty file", Format::ply, "", "empty"},
      {"not ply", Format::ply, "hello\n", "not a PLY"},
      {"no end_header", Format::ply, "ply\nformat ascii 1.0\nelement vertex 1\n", "end_header"},
      {"unknown format", Format::ply, "ply\nformat ebcdic 1.0\nend_header\n", "unknown PLY format"},
      {"unknown property type", Format::ply,
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n", "unknown property type"},
      {"lying header 2^31 faces", Format::ply, ply_header("binary_little_endian", 3, 2147483647) + std::string(36, '\0'),
       "too short"},
      {"truncated binary", Format::ply, truncated, "too short"},
      {"ascii too few vertices", Format::ply, ply_header("ascii", 4, 0) + tri, "too short"},
      {"ascii garbage token", Format::ply, ply_header("ascii", 3, 1) + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "line 11"},
      {"ascii index out of range", Format::ply, ply_header("ascii", 3, 1) + tri + "3 0 1 7\n", "index 7"},
      {"ascii negative index", Format::ply, ply_header("ascii", 3, 1) + tri + "3 0 -1 2\n", "invalid vertex index"},
      {"ascii face with 2 vertices", Format::ply, ply_header("ascii", 3, 1) + tri + "2 0 1\n", "2 vertices"},
      {"ascii nan coordinate", Format::ply, ply_header("ascii", 3, 1) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "non-finite"},
      {"ascii extra values", Format::ply, ply_header("ascii", 3, 1) + "0 0 0 9\n1 0 0\n0 1 0\n3 0 1 2\n", "more values"},
      {"no vertex element", Format::ply, "ply\nformat ascii 1.0\nend_header\n", "no vertex element"},
      {"obj bad number", Format::obj, "v 0 0 zero\n", "line 1"},
      {"obj index zero", Format::obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "out of range"},
      {"obj index past end", Format::obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "out of range"},
      {"obj relative index before start", Format::obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "out of range"},
      {"obj face with 2 vertices", Format::obj, "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3"},
      {"obj inf coordinate", Format::obj, "v 0 0 inf\n", "non-finite"},
      {"off missing header", Format::off, "3 1 0\n", "not an OFF"},
      {"off lying counts", Format::off, "OFF\n100000000 1 0\n0 0 0\n", "larger than the file"},
      {"off truncated", Format::off, "OFF\n3 1 0\n0 0 0\n1 0 0\n", "end of file"},
      {"off bad index", Format::off, "OFF\n3 1 0\n" + tri + "3 0 1 3\n", "out of range"},
      {"off face with 1 vertex", Format::off, "OFF\n3 1 0\n" + tri + "1 0\n", "at least 3"},
      {"stl too short", Format::stl, std::string(50, 'x'), "header"},
      {"stl wrong triangle count", Format::stl, std::string(80, ' ') + std::string("\x05\0\0\0", 4) + std::string(50, '\0'),
       "declares 5 triangles"},
      {"stl ascii garbage", Format::stl, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nbanana\n", "unexpected token"},
      {"stl ascii 2-vertex facet", Format::stl, "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
       "2 vertices"},
  };
}

TEST(MalformedInput, EveryCaseThrowsIoErrorNamingTheFileAndProblem) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    try {
      read_mesh_from_bytes(c.bytes, c.format, "bad-file.x");
      ADD_FAILURE() << "no exception for " << c.name;
    } catch (const IoError& e) {
      EXPECT_EQ(e.file(), "bad-file.x");
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
}

TEST(MalformedInput, MissingFileAndDirectoryNameThePath) {
  const std::string dir = test::temp_dir("malformed");
  try {
    read_mesh(dir + "/missing.ply");
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.ply"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos);
  }
  EXPECT_THROW(read_mesh(dir + "/"), UsageError);  // no extension to go by
  try {
    read_mesh(dir, Format::ply);
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("directory"), std::string::npos);
  }
}

}  // namespace
}  // namespace visimp
