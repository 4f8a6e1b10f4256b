#include "visimp/io/ply.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <ostream>
#include <sstream>
#include <vector>

#include "text_scanner.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "../core/large_array.h"

#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "visimp's binary readers assume a little-endian host"
#endif

namespace visimp {
namespace {

enum class Scalar : std::uint8_t { i8, u8, i16, u16, i32, u32, f32, f64 };

std::size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::i8:
    case Scalar::u8:
      return 1;
    case Scalar::i16:
    case Scalar::u16:
      return 2;
    case Scalar::i32:
    case Scalar::u32:
    case Scalar::f32:
      return 4;
    case Scalar::f64:
      return 8;
  }
  return 0;
}

std::optional<Scalar> parse_scalar(std::string_view t) {
  if (t == "char" || t == "int8") return Scalar::i8;
  if (t == "uchar" || t == "uint8") return Scalar::u8;
  if (t == "short" || t == "int16") return Scalar::i16;
  if (t == "ushort" || t == "uint16") return Scalar::u16;
  if (t == "int" || t == "int32") return Scalar::i32;
  if (t == "uint" || t == "uint32") return Scalar::u32;
  if (t == "float" || t == "float32") return Scalar::f32;
  if (t == "double" || t == "float64") return Scalar::f64;
  return std::nullopt;
}

struct Property {
  std::string name;
  Scalar type = Scalar::f32;
  bool is_list = false;
  Scalar count_type = Scalar::u8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Encoding { ascii, little, big };

struct Header {
  Encoding encoding = Encoding::ascii;
  std::vector<Element> elements;
  std::size_t body_offset = 0;  // byte offset of the first byte after end_header
  std::size_t body_line = 0;    // line number of the first body line (ascii)
};

Header parse_header(std::string_view bytes, const std::string& name) {
  Header h;
  detail::TextScanner sc(bytes, name);
  std::vector<std::string_view> tok;
  if (!sc.next_line() || sc.line() != "ply") throw IoError(name, "not a PLY file (missing 'ply' magic)");
  bool have_format = false;
  while (true) {
    if (!sc.next_line()) throw IoError(name, "PLY header has no end_header");
    sc.tokens(tok);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];
    if (key == "end_header") break;
    if (key == "comment" || key == "obj_info") continue;
    if (key == "format") {
      if (tok.size() != 3) sc.fail("malformed format line");
      if (tok[1] == "ascii")
        h.encoding = Encoding::ascii;
      else if (tok[1] == "binary_little_endian")
        h.encoding = Encoding::little;
      else if (tok[1] == "binary_big_endian")
        h.encoding = Encoding::big;
      else
        sc.fail("unknown PLY format '" + std::string(tok[1]) + "'");
      have_format = true;
    } else if (key == "element") {
      if (tok.size() != 3) sc.fail("malformed element line");
      Element e;
      e.name = std::string(tok[1]);
      const std::int64_t count = sc.to_int(tok[2], "element count");
      if (count < 0) sc.fail("negative element count");
      e.count = static_cast<std::uint64_t>(count);
      h.elements.push_back(std::move(e));
    } else if (key == "property") {
      if (h.elements.empty()) sc.fail("property before any element");
      Property p;
      if (tok.size() == 5 && tok[1] == "list") {
        const auto ct = parse_scalar(tok[2]);
        const auto it = parse_scalar(tok[3]);
        if (!ct || !it) sc.fail("unknown property type in list property '" + std::string(tok[4]) + "'");
        if (*ct == Scalar::f32 || *ct == Scalar::f64) sc.fail("list count type must be an integer");
        p.is_list = true;
        p.count_type = *ct;
        p.type = *it;
        p.name = std::string(tok[4]);
      } else if (tok.size() == 3) {
        const auto t = parse_scalar(tok[1]);
        if (!t) sc.fail("unknown property type '" + std::string(tok[1]) + "'");
        p.type = *t;
        p.name = std::string(tok[2]);
      } else {
        sc.fail("malformed property line");
      }
      h.elements.back().properties.push_back(std::move(p));
    } else {
      sc.fail("unexpected header line '" + std::string(sc.line().substr(0, 60)) + "'");
    }
  }
  if (!have_format) throw IoError(name, "PLY header has no format line");
  h.body_offset = bytes.size() - sc.remaining_bytes();
  h.body_line = sc.line_number() + 1;
  return h;
}

template <class T>
double load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return static_cast<double>(v);
}

// One value of type s at p, in the host's (little-endian) byte order.
double load_scalar(const char* p, Scalar s) {
  switch (s) {
    case Scalar::i8:
      return load<std::int8_t>(p);
    case Scalar::u8:
      return load<std::uint8_t>(p);
    case Scalar::i16:
      return load<std::int16_t>(p);
    case Scalar::u16:
      return load<std::uint16_t>(p);
    case Scalar::i32:
      return load<std::int32_t>(p);
    case Scalar::u32:
      return load<std::uint32_t>(p);
    case Scalar::f32:
      return load<float>(p);
    case Scalar::f64:
      return load<double>(p);
  }
  return 0;
}

// Reads scalars from a binary body with bounds checks; every failure names the byte offset.
class BinaryCursor {
 public:
  BinaryCursor(std::string_view bytes, std::size_t pos, bool big, const std::string& name)
      : bytes_(bytes), pos_(pos), big_(big), name_(name) {}

  double read(Scalar s) {
    const std::size_t n = scalar_size(s);
    if (pos_ + n > bytes_.size())
      throw IoError(name_, "byte " + std::to_string(pos_) + ": unexpected end of data (file truncated?)");
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + pos_, n);
    if (big_) std::reverse(raw, raw + n);
    pos_ += n;
    return load_scalar(reinterpret_cast<const char*>(raw), s);
  }
  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  std::string_view rest() const { return bytes_.substr(pos_); }
  void skip(std::size_t n) { pos_ += n; }

 private:
  std::string_view bytes_;
  std::size_t pos_;
  bool big_;
  const std::string& name_;
};

// One element's values, read the same way for ascii and binary bodies.
class BodyReader {
 public:
  virtual ~BodyReader() = default;
  virtual void begin_element_instance() = 0;
  virtual double scalar(Scalar type) = 0;
  virtual void end_element_instance() = 0;
  virtual std::size_t remaining_bytes() const = 0;
  /// Whether a list of n items of this type can still be present (bounds lying lengths).
  virtual bool can_hold_list(std::size_t n, Scalar type) const = 0;
  [[noreturn]] virtual void fail(const std::string& problem) const = 0;
};

class BinaryBody final : public BodyReader {
 public:
  BinaryBody(std::string_view bytes, std::size_t pos, bool big, const std::string& name)
      : cursor_(bytes, pos, big, name), name_(name), big_(big) {}
  void begin_element_instance() override { start_ = cursor_.pos(); }
  double scalar(Scalar type) override { return cursor_.read(type); }
  void end_element_instance() override {}
  std::size_t remaining_bytes() const override { return cursor_.remaining(); }
  bool can_hold_list(std::size_t n, Scalar type) const override { return n <= cursor_.remaining() / scalar_size(type); }
  [[noreturn]] void fail(const std::string& problem) const override {
    throw IoError(name_, "byte " + std::to_string(start_) + ": " + problem);
  }
  bool little_endian() const { return !big_; }
  std::string_view rest() const { return cursor_.rest(); }
  void skip(std::size_t n) { cursor_.skip(n); }

 private:
  BinaryCursor cursor_;
  const std::string& name_;
  bool big_;
  std::size_t start_ = 0;
};

// Which properties of an element read_ply uses (-1: none).
struct ElementRoles {
  bool is_vertex = false, is_face = false, have_vertices = false;
  int ix = -1, iy = -1, iz = -1, iq = -1, ilist = -1;
};

// The fast path for little-endian binary bodies (nearly every binary PLY): values are loaded at
// known offsets without a virtual call, a bounds check and a double per value. It reads one
// element whole or not at all: on anything unusual — data too short, a list that does not fit,
// an invalid index, a non-finite coordinate — it returns false having changed nothing, and the
// general reader reads the element again and names the problem exactly as before.
bool read_element_fast(BinaryBody& body, const Element& e, const ElementRoles& r, Mesh& mesh,
                       std::vector<std::uint32_t>& polygon) {
  if (!body.little_endian() || !(r.is_vertex || r.is_face)) return false;
  const std::string_view data = body.rest();
  const char* const first = data.data();
  const char* p = first;
  const char* const end = data.data() + data.size();
  const std::size_t faces_before = mesh.faces.size(), quality_before = mesh.face_quality.size();
  auto give_up = [&] {
    mesh.faces.resize(faces_before);
    mesh.face_quality.resize(quality_before);
    return false;
  };
  for (std::uint64_t i = 0; i < e.count; ++i) {
    double values[3] = {0, 0, 0};
    float quality = 0;
    polygon.clear();
    for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
      const Property& prop = e.properties[pi];
      const int at = static_cast<int>(pi);
      if (prop.is_list) {
        const std::size_t count_size = scalar_size(prop.count_type), item_size = scalar_size(prop.type);
        if (static_cast<std::size_t>(end - p) < count_size) return give_up();
        const double count = load_scalar(p, prop.count_type);
        p += count_size;
        if (!(count >= 0) || count > double(end - p) / double(item_size)) return give_up();
        const auto n = static_cast<std::size_t>(count);
        if (at == r.ilist) {
          for (std::size_t k = 0; k < n; ++k) {
            const double v = load_scalar(p + k * item_size, prop.type);
            if (!(v >= 0) || v != std::floor(v) || v > double(UINT32_MAX)) return give_up();
            polygon.push_back(static_cast<std::uint32_t>(v));
          }
        }
        p += n * item_size;
      } else {
        const std::size_t size = scalar_size(prop.type);
        if (static_cast<std::size_t>(end - p) < size) return give_up();
        if (at == r.ix || at == r.iy || at == r.iz || at == r.iq) {
          const double v = load_scalar(p, prop.type);
          if (at == r.ix)
            values[0] = v;
          else if (at == r.iy)
            values[1] = v;
          else if (at == r.iz)
            values[2] = v;
          else
            quality = static_cast<float>(v);
        }
        p += size;
      }
    }
    if (r.is_vertex) {
      const Vec3 position{values[0], values[1], values[2]};
      if (!is_finite(position)) return give_up();
      mesh.positions[i] = position;
      if (r.iq >= 0) mesh.vertex_quality[i] = quality;
    } else {
      if (polygon.size() < 3) return give_up();
      if (r.have_vertices)
        for (std::uint32_t v : polygon)
          if (v >= mesh.positions.size()) return give_up();
      detail::append_fan(polygon, mesh.faces);
      if (r.iq >= 0) mesh.face_quality.resize(mesh.faces.size(), quality);
    }
  }
  body.skip(static_cast<std::size_t>(p - first));
  return true;
}

// The commonest binary layouts, read without a per-value type switch: vertices whose
// properties are all fixed-size with x, y, z (and quality) as floats, and faces whose only
// property is a `list uchar int|uint` of indices, triangles copied whole. Like
// read_element_fast, an element is read whole or not at all (false: nothing changed), and the
// general readers name any problem. With the arrays in huge pages they halved reading the
// 14M-face mesh (1.17-1.29 s to 0.56-0.66 s; docs/formats.md, "Reading").
bool read_float_vertices(BinaryBody& body, const Element& e, const ElementRoles& r, Mesh& mesh) {
  if (!body.little_endian() || !r.is_vertex) return false;
  std::size_t stride = 0, offset[4] = {0, 0, 0, 0};
  const int roles[4] = {r.ix, r.iy, r.iz, r.iq};
  for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
    const Property& prop = e.properties[pi];
    if (prop.is_list) return false;
    for (int k = 0; k < 4; ++k) {
      if (roles[k] != static_cast<int>(pi)) continue;
      if (prop.type != Scalar::f32) return false;
      offset[k] = stride;
    }
    stride += scalar_size(prop.type);
  }
  const std::string_view data = body.rest();
  if (e.count > data.size() / stride) return false;
  const char* p = data.data();
  const auto value = [&](int k) {
    float v;
    std::memcpy(&v, p + offset[k], sizeof v);
    return v;
  };
  for (std::uint64_t i = 0; i < e.count; ++i, p += stride) {
    const Vec3 position{value(0), value(1), value(2)};
    if (!is_finite(position)) {
      mesh.positions.clear();
      mesh.vertex_quality.clear();
      return false;
    }
    mesh.positions.push_back(position);
    if (r.iq >= 0) mesh.vertex_quality.push_back(value(3));
  }
  body.skip(e.count * stride);
  return true;
}

static_assert(sizeof(Face) == 3 * sizeof(std::uint32_t), "a triangle's indices are copied whole");

bool read_index_lists(BinaryBody& body, const Element& e, const ElementRoles& r, Mesh& mesh,
                      std::vector<std::uint32_t>& polygon) {
  if (!body.little_endian() || !r.is_face || e.properties.size() != 1) return false;
  const Property& list = e.properties[0];
  if (!list.is_list || list.count_type != Scalar::u8 || (list.type != Scalar::i32 && list.type != Scalar::u32))
    return false;
  // Every valid index is below `limit`; a negative int read as unsigned is at least 2^31.
  std::uint64_t limit = list.type == Scalar::i32 ? std::uint64_t(INT32_MAX) + 1 : std::uint64_t(UINT32_MAX) + 1;
  if (r.have_vertices) limit = std::min<std::uint64_t>(limit, mesh.positions.size());
  const std::string_view data = body.rest();
  const char* p = data.data();
  const char* const end = p + data.size();
  const std::size_t faces_before = mesh.faces.size();
  for (std::uint64_t i = 0; i < e.count; ++i) {
    if (p == end) break;
    const std::size_t n = static_cast<unsigned char>(*p++);
    if (n < 3 || n * 4 > static_cast<std::size_t>(end - p)) break;
    if (n == 3) {
      Face face;
      std::memcpy(face.data(), p, sizeof face);
      if (!(face[0] < limit && face[1] < limit && face[2] < limit)) break;
      mesh.faces.push_back(face);
    } else {
      polygon.resize(n);
      std::memcpy(polygon.data(), p, n * 4);
      if (!std::all_of(polygon.begin(), polygon.end(), [&](std::uint32_t v) { return v < limit; })) break;
      detail::append_fan(polygon, mesh.faces);
    }
    p += n * 4;
    if (i + 1 == e.count) {
      body.skip(static_cast<std::size_t>(p - data.data()));
      return true;
    }
  }
  mesh.faces.resize(faces_before);
  return e.count == 0;
}

class AsciiBody final : public BodyReader {
 public:
  AsciiBody(std::string_view text, std::size_t first_line, const std::string& name)
      : scanner_(text, name, first_line) {}
  void begin_element_instance() override {
    do {
      if (!scanner_.next_line()) scanner_.fail("unexpected end of file (fewer elements than the header declares)");
      scanner_.tokens(tokens_);
    } while (tokens_.empty());
    next_ = 0;
  }
  double scalar(Scalar type) override {
    if (next_ >= tokens_.size()) scanner_.fail("too few values on the line");
    const std::string_view t = tokens_[next_++];
    if (type == Scalar::f32 || type == Scalar::f64) return scanner_.to_double(t, "a property");
    return static_cast<double>(scanner_.to_int(t, "an integer property"));
  }
  void end_element_instance() override {
    if (next_ != tokens_.size()) scanner_.fail("more values on the line than the header declares");
  }
  std::size_t remaining_bytes() const override { return scanner_.remaining_bytes() + 1; }
  bool can_hold_list(std::size_t n, Scalar) const override { return n <= tokens_.size() - next_; }
  [[noreturn]] void fail(const std::string& problem) const override { scanner_.fail(problem); }

 private:
  detail::TextScanner scanner_;
  std::vector<std::string_view> tokens_;
  std::size_t next_ = 0;
};

int find_property(const Element& e, std::initializer_list<std::string_view> names) {
  for (std::size_t i = 0; i < e.properties.size(); ++i)
    for (std::string_view n : names)
      if (e.properties[i].name == n) return static_cast<int>(i);
  return -1;
}

// The fewest bytes one element instance can take; bounds counts from a lying header.
std::size_t min_instance_bytes(const Element& e, Encoding enc) {
  std::size_t n = 0;
  for (const Property& p : e.properties)
    n += enc == Encoding::ascii ? 2 : (p.is_list ? scalar_size(p.count_type) : scalar_size(p.type));
  return n;
}

}  // namespace

Mesh read_ply(std::string_view bytes, const std::string& name) {
  const Header h = parse_header(bytes, name);
  std::unique_ptr<BodyReader> body;
  BinaryBody* binary = nullptr;
  if (h.encoding == Encoding::ascii) {
    body = std::make_unique<AsciiBody>(bytes.substr(h.body_offset), h.body_line, name);
  } else {
    auto b = std::make_unique<BinaryBody>(bytes, h.body_offset, h.encoding == Encoding::big, name);
    binary = b.get();
    body = std::move(b);
  }

  Mesh mesh;
  bool have_vertices = false;
  std::vector<std::uint32_t> polygon;
  for (const Element& e : h.elements) {
    const std::size_t min_bytes = min_instance_bytes(e, h.encoding);
    if (min_bytes > 0 && e.count > body->remaining_bytes() / min_bytes)
      throw IoError(name, "header declares " + std::to_string(e.count) + " '" + e.name +
                              "' elements but the file is too short to hold them");
    if (min_bytes == 0 && e.count > 0)
      throw IoError(name, "element '" + e.name + "' has no properties but a count of " + std::to_string(e.count));
    const bool is_vertex = e.name == "vertex" && !have_vertices;
    const bool is_face = e.name == "face";
    int ix = -1, iy = -1, iz = -1, iq = -1, ilist = -1;
    if (is_vertex) {
      ix = find_property(e, {"x"});
      iy = find_property(e, {"y"});
      iz = find_property(e, {"z"});
      iq = find_property(e, {"quality"});
      if (ix < 0 || iy < 0 || iz < 0) throw IoError(name, "vertex element lacks an x, y or z property");
      if (e.count > UINT32_MAX) throw IoError(name, "more than 2^32 vertices are not supported");
      detail::reserve_in_huge_pages(mesh.positions, e.count);
      if (iq >= 0) detail::reserve_in_huge_pages(mesh.vertex_quality, e.count);
    }
    if (is_face) {
      ilist = find_property(e, {"vertex_indices", "vertex_index"});
      iq = find_property(e, {"quality"});
      if (ilist < 0 || !e.properties[ilist].is_list) throw IoError(name, "face element lacks a vertex_indices list");
      detail::reserve_in_huge_pages(mesh.faces, e.count);
      if (iq >= 0 || mesh.has_face_quality()) detail::reserve_in_huge_pages(mesh.face_quality, e.count);
    }
    const ElementRoles roles{is_vertex, is_face, have_vertices, ix, iy, iz, iq, ilist};
    if (binary != nullptr && (read_float_vertices(*binary, e, roles, mesh) || read_index_lists(*binary, e, roles, mesh, polygon))) {
      if (is_vertex) have_vertices = true;
      continue;
    }
    if (is_vertex) {  // the readers below assign by index
      mesh.positions.resize(e.count);
      if (iq >= 0) mesh.vertex_quality.resize(e.count);
    }
    if (binary != nullptr && read_element_fast(*binary, e, roles, mesh, polygon)) {
      if (is_vertex) have_vertices = true;
      continue;
    }
    for (std::uint64_t i = 0; i < e.count; ++i) {
      body->begin_element_instance();
      double values[3] = {0, 0, 0};
      float quality = 0;
      polygon.clear();
      for (std::size_t pi = 0; pi < e.properties.size(); ++pi) {
        const Property& p = e.properties[pi];
        const int at = static_cast<int>(pi);
        if (p.is_list) {
          const double count = body->scalar(p.count_type);
          if (count < 0) body->fail("negative list length in element '" + e.name + "' " + std::to_string(i));
          const std::size_t n = static_cast<std::size_t>(count);
          if (!body->can_hold_list(n, p.type))
            body->fail("list of " + std::to_string(n) + " values is longer than the data that follows");
          for (std::size_t k = 0; k < n; ++k) {
            const double v = body->scalar(p.type);
            if (at == ilist) {
              if (!(v >= 0) || v != std::floor(v) || v > double(UINT32_MAX))
                body->fail("face " + std::to_string(i) + " has an invalid vertex index " + std::to_string(v));
              polygon.push_back(static_cast<std::uint32_t>(v));
            }
          }
        } else {
          const double v = body->scalar(p.type);
          if (at == ix)
            values[0] = v;
          else if (at == iy)
            values[1] = v;
          else if (at == iz)
            values[2] = v;
          else if (at == iq)
            quality = static_cast<float>(v);
        }
      }
      body->end_element_instance();
      if (is_vertex) {
        mesh.positions[i] = {values[0], values[1], values[2]};
        if (!is_finite(mesh.positions[i])) body->fail("vertex " + std::to_string(i) + " has a non-finite coordinate");
        if (iq >= 0) mesh.vertex_quality[i] = quality;
      } else if (is_face) {
        if (polygon.size() < 3)
          body->fail("face " + std::to_string(i) + " has " + std::to_string(polygon.size()) +
                     " vertices (at least 3 needed)");
        if (have_vertices)
          for (std::uint32_t v : polygon)
            if (v >= mesh.positions.size())
              body->fail("face " + std::to_string(i) + " has vertex index " + std::to_string(v) +
                         " >= " + std::to_string(mesh.positions.size()) + " vertices");
        detail::append_fan(polygon, mesh.faces);
        if (iq >= 0) mesh.face_quality.resize(mesh.faces.size(), quality);
      }
    }
    if (is_vertex) have_vertices = true;
  }
  if (!have_vertices) throw IoError(name, "PLY file has no vertex element");
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (VertexIndex v : mesh.faces[f])
      if (v >= mesh.positions.size())
        throw IoError(name, "face " + std::to_string(f) + " has vertex index " + std::to_string(v) +
                                " >= " + std::to_string(mesh.positions.size()) + " vertices");
  if (!mesh.face_quality.empty() && mesh.face_quality.size() != mesh.faces.size()) mesh.face_quality.clear();
  return mesh;
}

bool needs_double_precision(const Mesh& mesh) {
  const double tolerance = 1e-7 * bounding_box(mesh).diagonal();
  for (const Vec3& p : mesh.positions)
    for (int k = 0; k < 3; ++k)
      if (std::abs(double(static_cast<float>(p[k])) - p[k]) > tolerance) return true;
  return false;
}

namespace {

// Binary values gathered into one 1 MiB block and written out when it is full: a put is a
// copy, not a vector resize (those were a tenth of writing the 14M-face mesh).
class LittleEndianBuffer {
 public:
  explicit LittleEndianBuffer(std::ostream& out) : out_(out), data_(kChunk + kMaxElementBytes) {}
  template <class T>
  void put(T v) {
    std::memcpy(data_.data() + size_, &v, sizeof(T));
    size_ += sizeof(T);
  }
  // After each element: at most kMaxElementBytes are put between two calls.
  void end_element() {
    if (size_ >= kChunk) flush();
  }
  void flush() {
    out_.write(data_.data(), static_cast<std::streamsize>(size_));
    size_ = 0;
  }

 private:
  static constexpr std::size_t kChunk = std::size_t(1) << 20;
  static constexpr std::size_t kMaxElementBytes = 64;  // a vertex: 3 doubles and a float; a face: 21 bytes
  std::ostream& out_;
  std::vector<char> data_;
  std::size_t size_ = 0;
};

}  // namespace

void write_ply(const Mesh& mesh, std::ostream& out, const WriteOptions& options) {
  const bool use_double = options.force_double || needs_double_precision(mesh);
  const char* coord = use_double ? "double" : "float";
  out << "ply\nformat " << (options.binary ? "binary_little_endian" : "ascii") << " 1.0\n"
      << "comment generated by visimp\n"
      << "element vertex " << mesh.num_vertices() << "\n"
      << "property " << coord << " x\nproperty " << coord << " y\nproperty " << coord << " z\n";
  if (mesh.has_vertex_quality()) out << "property float quality\n";
  out << "element face " << mesh.num_faces() << "\nproperty list uchar int vertex_indices\n";
  if (mesh.has_face_quality()) out << "property float quality\n";
  const std::vector<std::uint32_t>* source = options.source_face;
  if (source && source->size() != mesh.num_faces()) source = nullptr;
  if (source) out << "property uint source_face\n";
  out << "end_header\n";

  if (!options.binary) {
    std::ostringstream line;
    line.precision(use_double ? 17 : 9);
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      const Vec3& p = mesh.positions[v];
      if (use_double)
        line << p.x << ' ' << p.y << ' ' << p.z;
      else
        line << float(p.x) << ' ' << float(p.y) << ' ' << float(p.z);
      if (mesh.has_vertex_quality()) line << ' ' << mesh.vertex_quality[v];
      line << '\n';
      out << line.str();
      line.str("");
    }
    for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
      const Face& t = mesh.faces[f];
      line << "3 " << t[0] << ' ' << t[1] << ' ' << t[2];
      if (mesh.has_face_quality()) line << ' ' << mesh.face_quality[f];
      if (source) line << ' ' << (*source)[f];
      line << '\n';
      out << line.str();
      line.str("");
    }
    return;
  }
  LittleEndianBuffer buf(out);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    for (int k = 0; k < 3; ++k) {
      if (use_double)
        buf.put<double>(p[k]);
      else
        buf.put<float>(static_cast<float>(p[k]));
    }
    if (mesh.has_vertex_quality()) buf.put<float>(mesh.vertex_quality[v]);
    buf.end_element();
  }
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    buf.put<std::uint8_t>(3);
    for (VertexIndex v : mesh.faces[f]) buf.put<std::int32_t>(static_cast<std::int32_t>(v));
    if (mesh.has_face_quality()) buf.put<float>(mesh.face_quality[f]);
    if (source) buf.put<std::uint32_t>((*source)[f]);
    buf.end_element();
  }
  buf.flush();
}

}  // namespace visimp
