// Meshes built in code with known answers, and the real meshes tests sweep over.
#pragma once

#include <string>
#include <vector>

#include "visimp/core/mesh.h"

namespace visimp::test {

/// A flat n×n grid of unit squares in the z = 0 plane, two triangles per square, normals +z.
/// Vertex (i, j) has index j*(n+1)+i and position (i, j, 0).
Mesh grid(int n);
/// The closed axis-aligned cube [0,1]^3, each side an n×n grid, outward normals.
Mesh subdivided_cube(int n);
/// A closed icosphere of radius r, subdivided `levels` times (20·4^levels faces).
Mesh icosphere(int levels, double radius = 1.0);

/// Paths of the bundled meshes in meshes/ plus those of ../shared/meshes, listed whether or
/// not the shared ones are present: a test must GTEST_SKIP (or note) an absent one by name,
/// never drop it silently. The dragon is left to bench/.
std::vector<std::string> real_mesh_paths(bool include_shared = true);
std::string bundled_mesh(const std::string& file);  // meshes/<file>, always present
std::string shared_mesh(const std::string& file);   // ../shared/meshes/<file>, may be absent

}  // namespace visimp::test
