#include "visimp/io/off.h"

#include <ostream>
#include <vector>

#include "text_scanner.h"

namespace visimp {
namespace {

// Next non-blank, non-comment line, split into tokens; fails with `what` at end of file.
void next_content_line(detail::TextScanner& sc, std::vector<std::string_view>& tok, const char* what) {
  while (sc.next_line()) {
    std::string_view line = sc.line();
    const std::size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    detail::TextScanner::split(line, tok);
    if (!tok.empty()) return;
  }
  sc.fail(std::string("unexpected end of file while reading ") + what);
}

}  // namespace

Mesh read_off(std::string_view text, const std::string& name) {
  detail::TextScanner sc(text, name);
  std::vector<std::string_view> tok;
  next_content_line(sc, tok, "the header");
  const std::string_view magic = tok[0];
  if (magic.size() < 3 || magic.substr(magic.size() - 3) != "OFF") sc.fail("not an OFF file (missing 'OFF' header)");
  if (magic.find('n') != std::string_view::npos || magic.find('4') != std::string_view::npos)
    sc.fail("only 3-dimensional OFF is supported");
  tok.erase(tok.begin());
  if (tok.empty()) next_content_line(sc, tok, "the counts");
  if (tok.size() < 2) sc.fail("expected vertex and face counts");
  const std::int64_t nv = sc.to_int(tok[0], "the vertex count");
  const std::int64_t nf = sc.to_int(tok[1], "the face count");
  if (nv < 0 || nf < 0) sc.fail("negative counts");
  // A vertex line takes at least 6 bytes ("0 0 0\n") and a face line at least 8.
  if (static_cast<std::uint64_t>(nv) > sc.remaining_bytes() / 6 + 1 ||
      static_cast<std::uint64_t>(nf) > sc.remaining_bytes() / 8 + 1)
    sc.fail("the counts (" + std::to_string(nv) + " vertices, " + std::to_string(nf) +
            " faces) are larger than the file can hold");
  Mesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(nv));
  for (std::int64_t i = 0; i < nv; ++i) {
    next_content_line(sc, tok, "vertices");
    if (tok.size() < 3) sc.fail("vertex needs 3 coordinates");
    const Vec3 p{sc.to_double(tok[0], "x"), sc.to_double(tok[1], "y"), sc.to_double(tok[2], "z")};
    if (!is_finite(p)) sc.fail("vertex has a non-finite coordinate");
    mesh.positions.push_back(p);
  }
  mesh.faces.reserve(static_cast<std::size_t>(nf));
  std::vector<std::uint32_t> polygon;
  for (std::int64_t i = 0; i < nf; ++i) {
    next_content_line(sc, tok, "faces");
    const std::int64_t n = sc.to_int(tok[0], "the face's vertex count");
    if (n < 3) sc.fail("face has " + std::to_string(n) + " vertices (at least 3 needed)");
    if (static_cast<std::size_t>(n) + 1 > tok.size()) sc.fail("face has fewer indices than its count");
    polygon.clear();
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t idx = sc.to_int(tok[static_cast<std::size_t>(k) + 1], "a face index");
      if (idx < 0 || idx >= nv)
        sc.fail("face index " + std::to_string(idx) + " is out of range (" + std::to_string(nv) + " vertices)");
      polygon.push_back(static_cast<std::uint32_t>(idx));
    }
    detail::append_fan(polygon, mesh.faces);
  }
  return mesh;
}

void write_off(const Mesh& mesh, std::ostream& out) {
  out.precision(17);
  out << "OFF\n" << mesh.num_vertices() << ' ' << mesh.num_faces() << " 0\n";
  for (const Vec3& p : mesh.positions) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  for (const Face& f : mesh.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

}  // namespace visimp
