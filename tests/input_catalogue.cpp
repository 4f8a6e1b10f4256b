// The bad-input catalogue (see input_catalogue.h). Every message fragment is what a user
// needs to find the problem: the line, the index, the declared count.
#include "input_catalogue.h"

#include <cmath>
#include <cstring>
#include <limits>

#include "test_meshes.h"

namespace visimp::test {
namespace {

std::string ply_header(const std::string& format, int nv, int nf) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(nv) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(nf) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string nan_binary_ply() {
  std::string s = ply_header("binary_little_endian", 3, 1);
  const float v[9] = {0, 0, 0, std::numeric_limits<float>::quiet_NaN(), 0, 0, 0, 1, 0};
  s.append(reinterpret_cast<const char*>(v), sizeof v);
  const unsigned char count = 3;
  const int idx[3] = {0, 1, 2};
  s.append(reinterpret_cast<const char*>(&count), 1);
  s.append(reinterpret_cast<const char*>(idx), sizeof idx);
  return s;
}

// Three valid vertices and one face with `count` and `indices` as given: the binary fast path
// must give these back to the general reader, whose messages name the problem.
std::string binary_face_ply(unsigned char count, const std::vector<int>& indices) {
  std::string s = ply_header("binary_little_endian", 3, 1);
  const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  s.append(reinterpret_cast<const char*>(v), sizeof v);
  s.append(reinterpret_cast<const char*>(&count), 1);
  s.append(reinterpret_cast<const char*>(indices.data()), indices.size() * sizeof(int));
  return s;
}

std::string inf_binary_stl() {
  std::string s(80, ' ');
  const std::uint32_t n = 1;
  s.append(reinterpret_cast<const char*>(&n), 4);
  const float t[12] = {0, 0, 1, 0, 0, 0, 1, 0, 0, 0, std::numeric_limits<float>::infinity(), 0};
  s.append(reinterpret_cast<const char*>(t), sizeof t);
  s.append(2, '\0');
  return s;
}

}  // namespace

std::vector<BadInput> bad_inputs() {
  const std::string tri = "0 0 0\n1 0 0\n0 1 0\n";
  std::string truncated = ply_header("binary_little_endian", 3, 1);
  truncated += std::string(20, '\0');  // 36 bytes of vertices expected
  return {
      {"empty file", "bad.ply", "", "empty"},
      {"not ply", "bad.ply", "hello\n", "not a PLY"},
      {"no end_header", "bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\n", "end_header"},
      {"unknown format", "bad.ply", "ply\nformat ebcdic 1.0\nend_header\n", "unknown PLY format"},
      {"unknown property type", "bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n0\n",
       "unknown property type"},
      {"lying header 2^31 faces", "bad.ply", ply_header("binary_little_endian", 3, 2147483647) + std::string(36, '\0'),
       "too short"},
      {"truncated binary", "bad.ply", truncated, "too short"},
      {"ascii too few vertices", "bad.ply", ply_header("ascii", 4, 0) + tri, "too short"},
      {"ascii garbage token", "bad.ply", ply_header("ascii", 3, 1) + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n", "line 11"},
      {"ascii index out of range", "bad.ply", ply_header("ascii", 3, 1) + tri + "3 0 1 7\n", "index 7"},
      {"ascii negative index", "bad.ply", ply_header("ascii", 3, 1) + tri + "3 0 -1 2\n", "invalid vertex index"},
      {"ascii face with 2 vertices", "bad.ply", ply_header("ascii", 3, 1) + tri + "2 0 1\n", "2 vertices"},
      {"ascii nan coordinate", "bad.ply", ply_header("ascii", 3, 1) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "non-finite"},
      {"ascii extra values", "bad.ply", ply_header("ascii", 3, 1) + "0 0 0 9\n1 0 0\n0 1 0\n3 0 1 2\n", "more values"},
      {"no vertex element", "bad.ply", "ply\nformat ascii 1.0\nend_header\n", "no vertex element"},
      {"obj bad number", "bad.obj", "v 0 0 zero\n", "line 1"},
      {"obj index zero", "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "out of range"},
      {"obj index past end", "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "out of range"},
      {"obj relative index before start", "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", "out of range"},
      {"obj face with 2 vertices", "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", "at least 3"},
      {"obj inf coordinate", "bad.obj", "v 0 0 inf\n", "non-finite"},
      {"off missing header", "bad.off", "3 1 0\n", "not an OFF"},
      {"off lying counts", "bad.off", "OFF\n100000000 1 0\n0 0 0\n", "larger than the file"},
      {"off truncated", "bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n", "end of file"},
      {"off bad index", "bad.off", "OFF\n3 1 0\n" + tri + "3 0 1 3\n", "out of range"},
      {"off face with 1 vertex", "bad.off", "OFF\n3 1 0\n" + tri + "1 0\n", "at least 3"},
      {"stl too short", "bad.stl", std::string(50, 'x'), "header"},
      {"stl wrong triangle count", "bad.stl",
       std::string(80, ' ') + std::string("\x05\0\0\0", 4) + std::string(50, '\0'), "declares 5 triangles"},
      {"stl ascii garbage", "bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nbanana\n",
       "unexpected token"},
      {"stl ascii 2-vertex facet", "bad.stl",
       "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
       "2 vertices"},
      // Added with the hardening issue.
      {"zero-byte obj", "bad.obj", "", "empty"},
      {"zero-byte off", "bad.off", "", "empty"},
      {"zero-byte stl", "bad.stl", "", "empty"},
      {"ply face with 0 vertices", "bad.ply", ply_header("ascii", 3, 1) + tri + "0\n", "0 vertices"},
      {"ply index beyond 2^32", "bad.ply", ply_header("ascii", 3, 1) + tri + "3 0 1 4294967296\n", "index"},
      {"ply binary nan", "bad.ply", nan_binary_ply(), "non-finite"},
      {"ply binary index out of range", "bad.ply", binary_face_ply(3, {0, 1, 7}), "index 7"},
      {"ply binary negative index", "bad.ply", binary_face_ply(3, {0, -1, 2}), "invalid vertex index"},
      {"ply binary face with 2 vertices", "bad.ply", binary_face_ply(2, {0, 1}), "2 vertices"},
      {"ply binary list past the end", "bad.ply", binary_face_ply(200, {0, 1, 2}), "longer than the data"},
      {"ply list count as float", "bad.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list float int vertex_indices\nend_header\n" +
           tri + "3 0 1 2\n",
       "list"},
      {"ply vertex without z", "bad.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nelement face 1\n"
       "property list uchar int vertex_indices\nend_header\n0 0\n1 0\n0 1\n3 0 1 2\n",
       "lacks an x, y or z"},
      {"off short vertex line", "bad.off", "OFF\n3 1 0\n0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "line 3"},
      {"obj garbage face", "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf a b c\n", "line 4"},
      {"obj comments only", "bad.obj", "# nothing\n", "not an OBJ"},
      {"off nan coordinate", "bad.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n", "non-finite"},
      {"off negative count", "bad.off", "OFF\n-3 1 0\n", "count"},
      {"stl binary inf", "bad.stl", inf_binary_stl(), "non-finite"},
      {"stl ascii truncated", "bad.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
       "ends inside a facet"},
      // Added with issue 18: nothing to simplify, measure or compare; formats the content
      // decides (the extension is missing, unknown or wrong) and that are still broken.
      {"ply vertices, no face element", "bad.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n" +
           tri,
       "no faces", true},
      {"ply zero vertices and faces", "bad.ply", ply_header("ascii", 0, 0), "no faces", true},
      {"ply vertices and an empty face element", "bad.ply", ply_header("ascii", 3, 0) + tri, "no faces", true},
      {"obj vertices only", "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces", true},
      {"off zero faces", "bad.off", "OFF\n3 0 0\n" + tri, "no faces", true},
      {"stl ascii solid without facets", "bad.stl", "solid x\nendsolid x\n", "no faces", true},
      {"stl binary zero triangles", "bad.stl", std::string(80, ' ') + std::string(4, '\0'), "no faces", true},
      {"unknown extension, unknown content", "bad.xyz", "hello\n", "unknown extension"},
      {"no extension, unknown content", "bad", "hello world\n", "no extension"},
      {"off content named ply, truncated", "bad.ply", "OFF\n3 1 0\n0 0 0\n1 0 0\n", "(OFF by its content)"},
      {"obj content named off, bad index", "bad.off", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 5\n", "(OBJ by its content)"},
      {"ply content named stl, bad index", "bad.stl", ply_header("ascii", 3, 1) + tri + "3 0 1 7\n",
       "(PLY by its content)"},
      {"stl content named obj, truncated", "bad.obj", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
       "(STL by its content)"},
      {"ply header only", "bad.ply", "ply\n", "end_header"},
      {"ply negative element count", "bad.ply", "ply\nformat ascii 1.0\nelement vertex -3\nend_header\n",
       "negative element count"},
      {"ply big-endian truncated", "bad.ply", ply_header("binary_big_endian", 3, 0) + "xx", "too short"},
      {"obj index beyond 2^32", "bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n", "out of range"},
      {"stl ascii nan", "bad.stl",
       "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 nan\nvertex 1 0 0\nvertex 0 1 "
       "0\nendloop\nendfacet\nendsolid\n",
       "non-finite"},
      {"off quad with a bad index", "bad.off", "OFF\n4 1 0\n" + tri + "1 1 0\n4 0 1 2 9\n", "out of range"},
      {"off face shorter than its count", "bad.off", "OFF\n3 1 0\n" + tri + "3 0 1\n", "fewer indices"},
  };
}

std::vector<ExtremeMesh> extreme_meshes() {
  std::vector<ExtremeMesh> out;
  const Mesh sphere = icosphere(3);
  auto transformed = [&](const std::string& name, double scale, const Vec3& offset) {
    Mesh m = sphere;
    for (Vec3& p : m.positions) p = p * scale + offset;
    out.push_back({name, m});
  };
  transformed("offset 1e7", 1.0, {1e7, -1e7, 1e7});
  transformed("scale 1e-9", 1e-9, {});
  transformed("scale 1e+9", 1e9, {});
  out.push_back({"coplanar grid", grid(30)});
  {
    Mesh m = grid(10);  // squashed to slivers: 1000:1
    for (Vec3& p : m.positions) p.y *= 1e-3;
    out.push_back({"slivers", m});
  }
  {
    Mesh m = sphere;  // 100k zero-area faces glued on
    for (std::size_t i = 0; i < 100000; ++i) {
      const VertexIndex v = static_cast<VertexIndex>(i % m.num_vertices());
      m.faces.push_back({v, v, static_cast<VertexIndex>((v + 1) % m.num_vertices())});
    }
    out.push_back({"100k zero-area faces", m});
  }
  {
    Mesh m = sphere;
    const std::size_t n = m.num_faces();
    for (std::size_t f = 0; f < n; f += 3) m.faces.push_back(m.faces[f]);
    out.push_back({"duplicate faces", m});
  }
  {
    Mesh m = grid(4);  // a fin on the middle row: three faces on one edge
    m.positions.push_back({2, 2, 1});
    m.faces.push_back({12, 13, static_cast<VertexIndex>(m.num_vertices() - 1)});
    out.push_back({"non-manifold edge", m});
  }
  {
    Mesh m = sphere;
    for (int i = 0; i < 50; ++i) m.positions.push_back({3.0 + i, 0, 0});
    out.push_back({"isolated vertices", m});
  }
  {
    Mesh m = sphere;  // one cap flipped, as exporters do to a patch
    for (Face& f : m.faces)
      if (m.positions[f[0]].x + m.positions[f[1]].x + m.positions[f[2]].x > 0.9) std::swap(f[1], f[2]);
    out.push_back({"inconsistent orientation", m});
  }
  return out;
}

}  // namespace visimp::test
