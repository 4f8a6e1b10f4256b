// Scene formats read through assimp (Debian libassimp-dev): glTF 2.0 (.gltf, .glb), 3MF,
// COLLADA (.dae), FBX and X3D. The scene's node tree is flattened with each node's transform
// (in double), polygons are triangulated, points and lines dropped, and each node's vertices
// are welded exactly as the STL reader welds (exact coordinates; nodes are not welded to each
// other, so parts that touch stay separate parts). Every node holding meshes is one group in
// FaceGroups, in depth-first document order. Read only: visimp writes PLY, OBJ, OFF and STL.
//
// assimp's errors become IoError naming the file ("part.glb: assimp: ..."), one line; so do the
// warnings in which assimp says it dropped part of the file (faces with bad indices).
#pragma once

#include <string>
#include <string_view>

#include "visimp/core/mesh.h"
#include "visimp/io/face_groups.h"
#include "visimp/io/mesh_io.h"

namespace visimp {

/// True for the formats this header reads (gltf, glb, 3mf, dae, fbx, x3d).
bool is_scene_format(Format format);

/// From a file: external resources (a .gltf's .bin buffers) are found beside it.
Mesh read_scene_file(const std::string& path, Format format, FaceGroups* groups = nullptr);

/// From memory (stdin, fuzzing): self-contained files only (a .gltf with external buffers fails).
Mesh read_scene_bytes(std::string_view bytes, Format format, const std::string& name, FaceGroups* groups = nullptr);

}  // namespace visimp
