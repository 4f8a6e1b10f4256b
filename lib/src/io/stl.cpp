#include "visimp/io/stl.h"

#include <cstring>
#include <ostream>
#include <vector>

#include "exact_welder.h"
#include "text_scanner.h"
#include "visimp/core/errors.h"

namespace visimp {
namespace {

using Welder = detail::ExactWelder;

bool looks_ascii(std::string_view bytes) {
  if (bytes.substr(0, 5) != "solid") return false;
  if (bytes.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, bytes.data() + 80, 4);
    if (84 + 50ull * n == bytes.size()) return false;  // a binary file whose header starts with "solid"
  }
  return bytes.find("facet") != std::string_view::npos || bytes.find("endsolid") != std::string_view::npos;
}

Mesh read_binary(std::string_view bytes, const std::string& name) {
  if (bytes.size() < 84) throw IoError(name, "binary STL shorter than its 84-byte header");
  std::uint32_t n;
  std::memcpy(&n, bytes.data() + 80, 4);
  const std::uint64_t expected = 84 + 50ull * n;
  if (expected != bytes.size())
    throw IoError(name, "binary STL declares " + std::to_string(n) + " triangles (" + std::to_string(expected) +
                            " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
  Mesh mesh;
  mesh.faces.reserve(n);
  Welder welder(mesh);
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + 84 + 50ull * t + 12;
    Face f;
    for (int k = 0; k < 3; ++k) {
      float xyz[3];
      std::memcpy(xyz, rec + 12 * k, 12);
      const Vec3 p{xyz[0], xyz[1], xyz[2]};
      if (!is_finite(p))
        throw IoError(name, "byte " + std::to_string(84 + 50ull * t) + ": triangle " + std::to_string(t) +
                                " has a non-finite coordinate");
      f[k] = welder.add(p);
    }
    mesh.faces.push_back(f);
  }
  return mesh;
}

Mesh read_ascii(std::string_view text, const std::string& name) {
  Mesh mesh;
  Welder welder(mesh);
  detail::TextScanner sc(text, name);
  std::vector<std::string_view> tok;
  std::vector<VertexIndex> loop;
  bool in_loop = false;
  while (sc.next_line()) {
    sc.tokens(tok);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    if (key == "vertex") {
      if (!in_loop) sc.fail("vertex outside an outer loop");
      if (tok.size() != 4) sc.fail("vertex needs 3 coordinates");
      const Vec3 p{sc.to_double(tok[1], "x"), sc.to_double(tok[2], "y"), sc.to_double(tok[3], "z")};
      if (!is_finite(p)) sc.fail("vertex has a non-finite coordinate");
      loop.push_back(welder.add(p));
    } else if (key == "outer") {
      in_loop = true;
      loop.clear();
    } else if (key == "endloop") {
      if (loop.size() != 3) sc.fail("facet has " + std::to_string(loop.size()) + " vertices (3 needed)");
      mesh.faces.push_back({loop[0], loop[1], loop[2]});
      in_loop = false;
    } else if (key != "solid" && key != "facet" && key != "endfacet" && key != "endsolid") {
      sc.fail("unexpected token '" + std::string(key.substr(0, 40)) + "'");
    }
  }
  if (in_loop) sc.fail("file ends inside a facet");
  return mesh;
}

}  // namespace

Mesh read_stl(std::string_view bytes, const std::string& name) {
  return looks_ascii(bytes) ? read_ascii(bytes, name) : read_binary(bytes, name);
}

void write_stl(const Mesh& mesh, std::ostream& out, bool binary) {
  auto unit_normal = [&mesh](const Face& f) {
    const Vec3 n = face_normal_unnormalized(mesh, f);
    const double len = norm(n);
    return len > 0 ? n / len : Vec3{};
  };
  if (!binary) {
    out.precision(9);
    out << "solid visimp\n";
    for (const Face& f : mesh.faces) {
      const Vec3 n = unit_normal(f);
      out << "facet normal " << n.x << ' ' << n.y << ' ' << n.z << "\n outer loop\n";
      for (VertexIndex v : f)
        out << "  vertex " << mesh.positions[v].x << ' ' << mesh.positions[v].y << ' ' << mesh.positions[v].z << '\n';
      out << " endloop\nendfacet\n";
    }
    out << "endsolid visimp\n";
    return;
  }
  char header[80] = {};
  std::strncpy(header, "binary STL written by visimp", sizeof header - 1);
  out.write(header, 80);
  const std::uint32_t n = static_cast<std::uint32_t>(mesh.num_faces());
  out.write(reinterpret_cast<const char*>(&n), 4);
  std::vector<char> record(50);
  for (const Face& f : mesh.faces) {
    float values[12];
    const Vec3 nrm = unit_normal(f);
    for (int k = 0; k < 3; ++k) values[k] = static_cast<float>(nrm[k]);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) values[3 + 3 * c + k] = static_cast<float>(mesh.positions[f[c]][k]);
    std::memcpy(record.data(), values, 48);
    record[48] = record[49] = 0;
    out.write(record.data(), 50);
  }
}

}  // namespace visimp
