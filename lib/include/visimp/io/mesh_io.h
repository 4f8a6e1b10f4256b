// Mesh file I/O: a dispatcher over one reader/writer per format (ply.h, obj.h, off.h, stl.h,
// and scene_formats.h for the formats read through assimp).
//
// What each format reads, writes and keeps:
//   PLY   read ascii, binary LE/BE, any scalar type (extra properties and elements skipped);
//         write binary LE or ascii; keeps shared and isolated vertices, vertex and face quality.
//   OBJ   read v, f (a, a/b, a//c, a/b/c, negative indices), o/g groups; write v, f;
//         keeps shared and isolated vertices.
//   OFF   read OFF/COFF/NOFF headers (colours skipped); write OFF; keeps shared and isolated vertices.
//   STL   read and write binary or ascii; vertices welded on read (exact coordinates).
//   glTF 2.0 (.gltf, .glb), 3MF, COLLADA (.dae), FBX, X3D: read only, through assimp; nodes
//         flattened with their transforms, welded per node as STL is; one group per node.
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
#include "visimp/io/face_groups.h"

namespace visimp {

/// ply, obj, off and stl are read and written by visimp's own readers and writers; the rest
/// are scene formats read through assimp (scene_formats.h), never written.
enum class Format { ply, obj, off, stl, gltf, glb, threemf, collada, fbx, x3d };

/// False for the read-only scene formats.
bool is_writable(Format format);

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

/// "ply", "obj", "off", "stl", "gltf", "glb", "3mf", "dae" (or "collada"), "fbx", "x3d"
/// (case-insensitive); nullopt otherwise.
std::optional<Format> parse_format(std::string_view name);
const char* format_name(Format format);
/// The format implied by a path's extension; throws UsageError when it has none we know.
Format format_from_path(const std::string& path);

/// The format the first bytes announce, or nullopt when they match none. The formats are told
/// apart without ambiguity: "ply" on the first line; an OFF keyword ([ST][C][N][4]OFF) as the
/// first token; a binary STL's size, 84 + 50 × its triangle count; "solid" followed by
/// "facet"; an OBJ keyword (v, vt, vn, f, o, g, ...) opening the first line that is not a
/// comment; "glTF" (binary glTF's magic); "Kaydara FBX Binary"; an XML root element
/// <COLLADA or <X3D; a JSON object with an "asset" member in its first 4 KiB (a .gltf: glTF 2.0
/// requires "asset"). A 3MF (a zip) is known by its extension only.
std::optional<Format> detect_format(std::string_view bytes);

/// How read_mesh chose the format of a file.
struct FormatChoice {
  Format format = Format::ply;
  /// True when the content decided: the path had no known extension (or was "-"), or its
  /// extension named another format than the bytes announce.
  bool detected = false;
};

/// Reads a mesh and the object each face belongs to: OBJ `o`/`g` groups, a scene file's nodes;
/// one group ("") for PLY, OFF and STL.
Mesh read_mesh_with_groups(const std::string& path, FaceGroups& groups, std::optional<Format> format = std::nullopt);

/// Reads a mesh file. Without an explicit format the extension decides, unless the content
/// announces another format (then the content wins) or the path has none (stdin "-", no
/// extension): then the content decides. Throws IoError (unreadable, malformed, no format
/// recognised, or invalid content such as NaN coordinates).
Mesh read_mesh(const std::string& path, std::optional<Format> format = std::nullopt, FormatChoice* choice = nullptr);
/// Reads from memory or a stream; `name` is used in error messages.
Mesh read_mesh_from_bytes(std::string_view bytes, Format format, const std::string& name);
/// The same, also reporting each face's group (as read_mesh_with_groups).
Mesh read_mesh_from_bytes(std::string_view bytes, Format format, const std::string& name, FaceGroups* groups);
Mesh read_mesh(std::istream& in, Format format, const std::string& name);

/// Writes a mesh atomically: to a temporary file beside `path`, renamed into place only after
/// a complete write. path "-" writes standard output. Throws IoError.
void write_mesh(const Mesh& mesh, const std::string& path, std::optional<Format> format = std::nullopt,
                const WriteOptions& options = {});
void write_mesh(const Mesh& mesh, std::ostream& out, Format format, const WriteOptions& options = {});

/// Reads a whole file (or stdin for "-") into memory. Throws IoError.
std::string read_file_bytes(const std::string& path);

}  // namespace visimp
