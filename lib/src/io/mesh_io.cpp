#include "visimp/io/mesh_io.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <sstream>

#include "visimp/core/errors.h"
#include "visimp/core/validate.h"
#include "visimp/io/atomic_file.h"
#include "visimp/io/obj.h"
#include "visimp/io/off.h"
#include "visimp/io/ply.h"
#include "visimp/io/stl.h"

namespace visimp {

std::optional<Format> parse_format(std::string_view name) {
  std::string lower(name);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "ply") return Format::ply;
  if (lower == "obj") return Format::obj;
  if (lower == "off") return Format::off;
  if (lower == "stl") return Format::stl;
  return std::nullopt;
}

const char* format_name(Format format) {
  switch (format) {
    case Format::ply: return "ply";
    case Format::obj: return "obj";
    case Format::off: return "off";
    case Format::stl: return "stl";
  }
  return "?";
}

Format format_from_path(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  const auto format = ext.empty() ? std::nullopt : parse_format(ext.substr(1));
  if (!format) throw UsageError(path + ": unknown mesh format '" + ext + "' (use .ply, .obj, .off or .stl, or --format)");
  return *format;
}

std::string read_file_bytes(const std::string& path) {
  if (path == "-") {
    std::ostringstream all;
    all << std::cin.rdbuf();
    return all.str();
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw IoError(path, "is a directory, not a mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path, std::string("cannot open: ") + std::strerror(errno));
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(path, "read error");
  return bytes;
}

Mesh read_mesh_from_bytes(std::string_view bytes, Format format, const std::string& name) {
  if (bytes.empty()) throw IoError(name, "file is empty");
  Mesh mesh;
  switch (format) {
    case Format::ply: mesh = read_ply(bytes, name); break;
    case Format::obj: mesh = read_obj(bytes, name); break;
    case Format::off: mesh = read_off(bytes, name); break;
    case Format::stl: mesh = read_stl(bytes, name); break;
  }
  const ValidationReport report = validate(mesh);
  if (!report.ok()) throw IoError(name, report.first_problem);
  return mesh;
}

Mesh read_mesh(std::istream& in, Format format, const std::string& name) {
  std::ostringstream all;
  all << in.rdbuf();
  return read_mesh_from_bytes(all.str(), format, name);
}

Mesh read_mesh(const std::string& path, std::optional<Format> format) {
  if (path == "-" && !format) throw UsageError("reading standard input needs an explicit --format");
  const Format f = format ? *format : format_from_path(path);
  const std::string name = path == "-" ? std::string("<stdin>") : path;
  return read_mesh_from_bytes(read_file_bytes(path), f, name);
}

void write_mesh(const Mesh& mesh, std::ostream& out, Format format, const WriteOptions& options) {
  switch (format) {
    case Format::ply: write_ply(mesh, out, options); break;
    case Format::obj: write_obj(mesh, out); break;
    case Format::off: write_off(mesh, out); break;
    case Format::stl: write_stl(mesh, out, options.binary); break;
  }
}

void write_mesh(const Mesh& mesh, const std::string& path, std::optional<Format> format, const WriteOptions& options) {
  require_valid(mesh, path);
  if (path == "-" && !format) throw UsageError("writing standard output needs an explicit --format");
  const Format f = format ? *format : format_from_path(path);
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
