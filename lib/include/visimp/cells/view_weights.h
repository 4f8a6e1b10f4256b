// What the walkthrough-LOD paper's preprocessing reads off images taken inside a cell
// (../shared/papers/002_*, §3.1):
//   - the object's depth image at the cell centre, whose depth variation weights the
//     vertices for the SVMesh collapse cost: exterior silhouettes weigh most, then interior
//     silhouettes (depth jumps) and sharp edges (depth creases), smooth parts least;
//   - the self-occluding-error test: an SVMesh keeps only the faces front-facing to the
//     centre, so an eye elsewhere in the cell may see holes where those faces end. s is the
//     width in pixels of the largest such hole seen from the cell's corners; s ≤ Ts means an
//     SVMesh will do, otherwise the object needs an MVMesh.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "visimp/core/mesh.h"
#include "visimp/render/perspective.h"

namespace visimp {

/// An object's perspective depth image from `eye`, looking at its bounding-box centre with a
/// field of view that just holds its bounding sphere (at most 170°).
struct DepthImage {
  PerspectiveView view;
  std::vector<std::uint32_t> ids;  ///< face + 1, 0 = background
  std::vector<float> distance;     ///< along the view direction; infinity for background
};
DepthImage capture_depth(const Mesh& mesh, const Vec3& eye, int resolution);

/// Per vertex, in [0, 1]: 1 on an exterior silhouette (a pixel around the vertex borders the
/// background), a depth jump between neighbouring pixels of more than 5% of the distance
/// counts as an interior silhouette (0.75), and a crease weighs its second difference of
/// depth against the local slope (up to 0.5); vertices the image does not show weigh 0.
std::vector<float> depth_variation_weights(const Mesh& mesh, const DepthImage& image);

/// The paper's self-occluding error, in pixels of a `resolution`² view with `fov_degrees`:
/// from each corner, the object drawn whole and drawn with only the faces front-facing to
/// `centre`; a pixel showing the object in the first but not in the second is a hole pixel,
/// and its width is the shorter of the horizontal and vertical runs of hole pixels through
/// it. s is the largest width over all corners (0: no hole anywhere).
double self_occluding_error(const Mesh& mesh, const Vec3& centre, const std::array<Vec3, 6>& corners, int resolution,
                            double fov_degrees);
/// The same for a given set of kept faces (a cluster's: front-facing to the centre and not
/// hidden there by the cluster's other objects).
double self_occluding_error(const Mesh& mesh, const std::vector<std::uint32_t>& kept,
                            const std::array<Vec3, 6>& corners, int resolution, double fov_degrees);

}  // namespace visimp
