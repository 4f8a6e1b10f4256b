// Mesh file I/O: a dispatcher over one reader/writer per format (ply.h, obj.h, off.h, stl.h).
//
// Capability table (what a round trip through each format keeps):
//
// | format | read                         | write             | shared vertices | vertex quality | face quality |
// isolated vertices |
// |--------|------------------------------|-------------------|-----------------|----------------|--------------|-------------------|
// | PLY    | ascii, binary LE/BE, any     | binary LE, ascii  | yes             | yes            | yes          | yes |
// |        | scalar type, extra props     |                   |                 |                |              | | |
// | and elements skipped         |                   |                 |                |              | | | OBJ    |
// v, f (a, a/b, a//c, a/b/c,   | v, f              | yes             | no             | no           | yes | |        |
// negative indices)            |                   |                 |                |              | | | OFF    |
// OFF/COFF/NOFF headers,       | OFF               | yes             | no             | no           | yes | |        |
// colours skipped              |                   |                 |                |              | | | STL    |
// binary, ascii                | binary, ascii     | welded on read  | no             | no           | no |
//
// Polygons with more than 3 vertices are fan-triangulated on read; a face with fewer than 3
// vertices is an error (never silently dropped). Every reader throws IoError naming the file
// and the line or byte offset, and checks counts against the data actually present before
// allocating, so a lying header cannot cause an unbounded allocation.
#pragma once

#include <iosfwd>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp {

enum class Format { ply, obj, off, stl };

struct WriteOptions {
  /// PLY and STL: binary (little-endian) when true, ASCII when false. Ignored by OBJ/OFF.
  bool binary = true;
  /// PLY coordinates: float unless a coordinate would move by more than 1e-7 of the bounding-box
  /// diagonal in float (meshes far from the origin), then double. Force double with true.
  bool force_double = false;
  /// PLY only: when set (one entry per face), also write the face property `uint source_face`
  /// (which input face each face came from, for culled or filtered meshes).
  const std::vector<std::uint32_t>* source_face = nullptr;
};

/// "ply", "obj", "off", "stl" (case-insensitive); nullopt otherwise.
std::optional<Format> parse_format(std::string_view name);
const char* format_name(Format format);
/// The format implied by a path's extension; throws UsageError when it has none we know.
Format format_from_path(const std::string& path);

/// The format the first bytes announce, or nullopt when they match none. The four formats
/// are told apart without ambiguity: "ply" on the first line; an OFF keyword ([ST][C][N][4]OFF)
/// as the first token; a binary STL's size, 84 + 50 × its triangle count; "solid" followed by
/// "facet"; an OBJ keyword (v, vt, vn, f, o, g, ...) opening the first line that is not a comment.
std::optional<Format> detect_format(std::string_view bytes);

/// How read_mesh chose the format of a file.
struct FormatChoice {
  Format format = Format::ply;
  /// True when the content decided: the path had no known extension (or was "-"), or its
  /// extension named another format than the bytes announce.
  bool detected = false;
};

/// Reads a mesh file. Without an explicit format the extension decides, unless the content
/// announces another format (then the content wins) or the path has none (stdin "-", no
/// extension): then the content decides. Throws IoError (unreadable, malformed, no format
/// recognised, or invalid content such as NaN coordinates).
Mesh read_mesh(const std::string& path, std::optional<Format> format = std::nullopt, FormatChoice* choice = nullptr);
/// Reads from memory or a stream; `name` is used in error messages.
Mesh read_mesh_from_bytes(std::string_view bytes, Format format, const std::string& name);
Mesh read_mesh(std::istream& in, Format format, const std::string& name);

/// Writes a mesh atomically: to a temporary file beside `path`, renamed into place only after
/// a complete write. path "-" writes standard output. Throws IoError.
void write_mesh(const Mesh& mesh, const std::string& path, std::optional<Format> format = std::nullopt,
                const WriteOptions& options = {});
void write_mesh(const Mesh& mesh, std::ostream& out, Format format, const WriteOptions& options = {});

/// Reads a whole file (or stdin for "-") into memory. Throws IoError.
std::string read_file_bytes(const std::string& path);

}  // namespace visimp
