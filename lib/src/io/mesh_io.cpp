#include "visimp/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "visimp/core/errors.h"
#include "visimp/core/validate.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/obj.h"
#include "visimp/io/off.h"
#include "visimp/io/ply.h"
#include "visimp/io/scene_formats.h"
#include "visimp/io/stl.h"
#include "../core/large_array.h"

namespace visimp {

std::optional<Format> parse_format(std::string_view name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "ply") return Format::ply;
  if (lower == "obj") return Format::obj;
  if (lower == "off") return Format::off;
  if (lower == "stl") return Format::stl;
  if (lower == "gltf") return Format::gltf;
  if (lower == "glb") return Format::glb;
  if (lower == "3mf") return Format::threemf;
  if (lower == "dae" || lower == "collada") return Format::collada;
  if (lower == "fbx") return Format::fbx;
  if (lower == "x3d") return Format::x3d;
  return std::nullopt;
}

bool is_writable(Format format) { return !is_scene_format(format); }

const char* format_name(Format format) {
  switch (format) {
    case Format::ply:
      return "ply";
    case Format::obj:
      return "obj";
    case Format::off:
      return "off";
    case Format::stl:
      return "stl";
    case Format::gltf:
      return "gltf";
    case Format::glb:
      return "glb";
    case Format::threemf:
      return "3mf";
    case Format::collada:
      return "dae";
    case Format::fbx:
      return "fbx";
    case Format::x3d:
      return "x3d";
  }
  return "?";
}

Format format_from_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  const auto format = ext.empty() ? std::nullopt : parse_format(ext.substr(1));
  if (!format)
    throw UsageError(path + ": unknown mesh format '" + ext + "' (use .ply, .obj, .off or .stl, or name the format)");
  return *format;
}

namespace {

// Reads `in` to its end into `bytes`, sized beforehand to what is expected (a regular file's
// size, else 0): that part in one read straight into the array, the rest — a file that grew, a
// pipe, standard input — in 64 KiB blocks. (Read a character at a time through
// istreambuf_iterator, a 265 MB PLY once took 1.2 s; through a 1 MiB block into a string, a
// copy and page faults for both.)
template <class Bytes>
void read_into(std::istream& in, Bytes& bytes) {
  if (!bytes.empty()) {
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<std::size_t>(in.gcount()));  // shorter if the file shrank meanwhile
  }
  std::vector<char> block(std::size_t{1} << 16);
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0)
    bytes.insert(bytes.end(), block.data(), block.data() + in.gcount());
}

// A named file opened to be read whole, with its size (0 when it has none: a pipe, a device);
// a directory or a file that cannot be opened is an IoError naming it.
std::ifstream open_whole_file(const std::string& path, std::size_t& size) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path, "is a directory, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, std::string("cannot open: ") + std::strerror(errno));
  const std::uintmax_t bytes = std::filesystem::is_regular_file(path, ec) ? std::filesystem::file_size(path, ec) : 0;
  size = ec ? 0 : static_cast<std::size_t>(bytes);
  return in;
}

}  // namespace

std::string read_file_bytes(const std::string& path) {
  std::string bytes;
  if (path == "-") {
    read_into(std::cin, bytes);
    if (std::cin.bad()) throw IoError(path, "read error on standard input");
    return bytes;
  }
  std::size_t size = 0;
  std::ifstream in = open_whole_file(path, size);
  bytes.resize(size);
  read_into(in, bytes);
  if (in.bad()) throw IoError(path, "read error");
  return bytes;
}

namespace {

// One byte of a file being read: its constructor leaves it unwritten, so sizing the array
// costs no pass over it (value-initialised chars were a 265 MB memset at 14M faces).
struct FileByte {
  char value;
  FileByte() {}  // NOLINT: deliberately leaves `value` uninitialised; the read fills it
  FileByte(char c) : value(c) {}  // NOLINT(google-explicit-constructor): insert() from chars
};
static_assert(sizeof(FileByte) == 1, "a FileByte array is read as chars");
using FileBytes = detail::LargeArray<FileByte>;

std::string_view view_of(const FileBytes& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

// A mesh file's bytes, read into one array huge-page backed from 64 KiB (core/large_array.h)
// and not zeroed first: the D-sub connector's 2.4 MB took ~850 page faults through a string,
// a quarter of reading it.
FileBytes read_whole_file(const std::string& path) {
  std::size_t size = 0;
  std::ifstream in = open_whole_file(path, size);
  FileBytes bytes(size);
  read_into(in, bytes);
  if (in.bad()) throw IoError(path, "read error");
  return bytes;
}

Mesh validated(Mesh mesh, const std::string& name) {
  const ValidationReport report = validate(mesh);
  if (!report.ok()) throw IoError(name, report.first_problem);
  return mesh;
}

}  // namespace

Mesh read_mesh_from_bytes(std::string_view bytes, Format format, const std::string& name) {
  return read_mesh_from_bytes(bytes, format, name, nullptr);
}

Mesh read_mesh_from_bytes(std::string_view bytes, Format format, const std::string& name, FaceGroups* groups) {
  if (bytes.empty()) throw IoError(name, "file is empty");
  Mesh mesh;
  switch (format) {
    case Format::ply:
      mesh = read_ply(bytes, name);
      break;
    case Format::obj:
      mesh = read_obj(bytes, name, groups);
      groups = nullptr;  // read_obj filled them
      break;
    case Format::off:
      mesh = read_off(bytes, name);
      break;
    case Format::stl:
      mesh = read_stl(bytes, name);
      break;
    case Format::gltf:
    case Format::glb:
    case Format::threemf:
    case Format::collada:
    case Format::fbx:
    case Format::x3d:
      mesh = read_scene_bytes(bytes, format, name, groups);
      groups = nullptr;
      break;
  }
  if (groups != nullptr) *groups = {{""}, std::vector<std::uint32_t>(mesh.num_faces(), 0)};
  return validated(std::move(mesh), name);
}

Mesh read_mesh(std::istream& in, Format format, const std::string& name) {
  std::string bytes;
  read_into(in, bytes);
  if (in.bad()) throw IoError(name, "read error");
  return read_mesh_from_bytes(bytes, format, name);
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v'; }

// The first whitespace-separated token of the first line that is neither blank nor a '#' comment.
std::string_view first_token(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_space(text[i])) ++i;
    if (i < text.size() && text[i] == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    std::size_t end = i;
    while (end < text.size() && !is_space(text[end])) ++end;
    return text.substr(i, end - i);
  }
  return {};
}

bool is_off_keyword(std::string_view t) {
  // [ST][C][N][4][n]OFF (Geomview's optional prefixes), e.g. OFF, COFF, NOFF, STCNOFF, 4OFF.
  if (t.size() < 3 || t.substr(t.size() - 3) != "OFF") return false;
  for (const char c : t.substr(0, t.size() - 3)) {
    if (std::string_view("STCN4n").find(c) == std::string_view::npos) return false;
  }
  return true;
}

// The root element of an XML document, when `head` is one: "<COLLADA" or "<X3D" after the
// prolog (<?xml ...?>, comments, a DOCTYPE).
bool xml_root_is(std::string_view head, std::string_view element) {
  if (head.substr(0, 3) == "\xEF\xBB\xBF") head.remove_prefix(3);  // UTF-8 byte-order mark
  std::size_t i = 0;
  while (i < head.size()) {
    while (i < head.size() && is_space(head[i])) ++i;
    if (i >= head.size() || head[i] != '<') return false;
    if (head.substr(i, 2) == "<?" || head.substr(i, 2) == "<!") {  // prolog, comment, DOCTYPE
      const std::size_t end = head.find('>', i);
      if (end == std::string_view::npos) return false;
      i = end + 1;
      continue;
    }
    const std::string_view tag = head.substr(i + 1, element.size());
    const std::size_t after = i + 1 + element.size();
    return tag == element && after < head.size() && (is_space(head[after]) || head[after] == '>');
  }
  return false;
}

}  // namespace

std::optional<Format> detect_format(std::string_view bytes) {
  if (bytes.size() >= 4 && bytes.substr(0, 3) == "ply" && (bytes[3] == '\n' || bytes[3] == '\r')) return Format::ply;
  if (bytes.size() >= 12 && bytes.substr(0, 4) == "glTF") return Format::glb;
  if (bytes.substr(0, 18) == "Kaydara FBX Binary") return Format::fbx;
  if (bytes.size() >= 84) {
    std::uint32_t triangles = 0;
    std::memcpy(&triangles, bytes.data() + 80, 4);  // little-endian, as STL is
    if (84 + 50 * static_cast<std::uint64_t>(triangles) == bytes.size()) return Format::stl;
  }
  const std::string_view head = bytes.substr(0, 4096);
  const std::string_view token = first_token(head);
  if (token == "solid" && bytes.substr(0, 4096).find("facet") != std::string_view::npos) return Format::stl;
  if (is_off_keyword(token)) return Format::off;
  for (const char* keyword : {"v", "vt", "vn", "vp", "f", "l", "p", "o", "g", "s", "mtllib", "usemtl"}) {
    if (token == keyword) return Format::obj;
  }
  if (xml_root_is(head, "COLLADA")) return Format::collada;
  if (xml_root_is(head, "X3D")) return Format::x3d;
  if (token.substr(0, 1) == "{" && head.find("\"asset\"") != std::string_view::npos) return Format::gltf;
  return std::nullopt;
}

namespace {

Mesh read_any(const std::string& path, std::optional<Format> format, FormatChoice* choice, FaceGroups* groups) {
  const std::string name = path == "-" ? std::string("<stdin>") : path;
  std::string from_stdin;
  FileBytes from_file;
  if (path == "-")
    from_stdin = read_file_bytes(path);
  else
    from_file = read_whole_file(path);
  const std::string_view bytes = path == "-" ? std::string_view(from_stdin) : view_of(from_file);
  FormatChoice chosen;
  if (format) {
    chosen.format = *format;
  } else {
    const std::string ext = path == "-" ? std::string() : std::filesystem::path(path).extension().string();
    // Plain flags, not optionals: GCC 12 warns (wrongly) that a disengaged one may be read.
    Format extension_format = Format::ply, content_format = Format::ply;
    bool has_extension = false, has_content = false;
    if (const auto f = ext.empty() ? std::nullopt : parse_format(ext.substr(1))) {
      extension_format = *f;
      has_extension = true;
    }
    if (const auto f = detect_format(bytes)) {
      content_format = *f;
      has_content = true;
    }
    if (has_extension && (!has_content || content_format == extension_format)) {
      chosen.format = extension_format;  // a broken file of the named format gets that reader's error
    } else if (has_content) {
      chosen = {content_format, true};
    } else if (bytes.empty()) {
      throw IoError(name, "file is empty");
    } else {
      throw IoError(name, (ext.empty() ? std::string("no extension") : "unknown extension '" + ext + "'") +
                              ", and the content is none of PLY, OBJ, OFF, STL, glTF, GLB, FBX, COLLADA or X3D (name the format explicitly)");
    }
  }
  if (choice != nullptr) *choice = chosen;
  // A scene file is read by assimp from its path, so a .gltf finds the buffers beside it.
  if (is_scene_format(chosen.format) && path != "-" && !bytes.empty()) {
    Mesh mesh = read_scene_file(path, chosen.format, groups);
    return validated(std::move(mesh), name);
  }
  if (!chosen.detected) return read_mesh_from_bytes(bytes, chosen.format, name, groups);
  // Say which reader the content chose, or the error would puzzle ("x.obj: not a PLY ...").
  std::string upper = format_name(chosen.format);
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return read_mesh_from_bytes(bytes, chosen.format, name + " (" + upper + " by its content)", groups);
}

}  // namespace

Mesh read_mesh(const std::string& path, std::optional<Format> format, FormatChoice* choice) {
  return read_any(path, format, choice, nullptr);
}

Mesh read_mesh_with_groups(const std::string& path, FaceGroups& groups, std::optional<Format> format) {
  return read_any(path, format, nullptr, &groups);
}

void write_mesh(const Mesh& mesh, std::ostream& out, Format format, const WriteOptions& options) {
  switch (format) {
    case Format::ply:
      write_ply(mesh, out, options);
      break;
    case Format::obj:
      write_obj(mesh, out);
      break;
    case Format::off:
      write_off(mesh, out);
      break;
    case Format::stl:
      write_stl(mesh, out, options.binary);
      break;
    case Format::gltf:
    case Format::glb:
    case Format::threemf:
    case Format::collada:
    case Format::fbx:
    case Format::x3d:
      throw UsageError(std::string("visimp reads ") + format_name(format) +
                       " but does not write it (write .ply, .obj, .off or .stl)");
  }
}

void write_mesh(const Mesh& mesh, const std::string& path, std::optional<Format> format, const WriteOptions& options) {
  require_valid(mesh, path);
  if (path == "-" && !format) throw UsageError("writing standard output needs an explicit format");
  const Format f = format ? *format : format_from_path(path);
  if (!is_writable(f))
    throw UsageError(path + ": visimp reads " + format_name(f) + " but does not write it (write .ply, .obj, .off or .stl)");
  if (path == "-") {
    write_mesh(mesh, std::cout, f, options);
    std::cout.flush();
    if (!std::cout) throw IoError("<stdout>", "write failed");
    return;
  }
  AtomicFileWriter writer(path);
  write_mesh(mesh, writer.stream(), f, options);
  writer.commit();
}

}  // namespace visimp
