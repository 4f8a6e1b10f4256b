// Winding repair by visibility (see orient.h).
#include "visimp/visibility/orient.h"

#include <utility>

#include "visimp/core/errors.h"
#include "visimp/core/orientation.h"

namespace visimp {

OrientResult orient_by_visibility(const Mesh& mesh, const Visibility& visibility, const OrientOptions& options) {
  const std::size_t n = mesh.num_faces();
  if (visibility.face_front.size() != n || visibility.face_back.size() != n) {
    throw UsageError("orienting needs V of both sides of every face: got " +
                     std::to_string(visibility.face_front.size()) + " for " + std::to_string(n) + " faces");
  }
  if (!(options.both_sides_threshold >= 0 && options.both_sides_threshold < 1)) {
    throw UsageError("both_sides_threshold must be in [0, 1)");
  }
  const OrientationPatches patches = orientation_patches(mesh, options.threads);
  enum class Decision : std::uint8_t { keep, reverse, both_sides, unseen };
  std::vector<Decision> decision(n, Decision::unseen);
  // Per patch: area of the seen faces that want the patch's canonical winding, and the other.
  std::vector<double> agree(patches.patches(), 0.0), disagree(patches.patches(), 0.0);
  for (std::size_t f = 0; f < n; ++f) {
    const float front = visibility.face_front[f], back = visibility.face_back[f];
    const double threshold = options.both_sides_threshold;
    if (front > threshold && back > threshold)
      decision[f] = Decision::both_sides;
    else if (back > front)
      decision[f] = Decision::reverse;
    else if (front > 0)
      decision[f] = Decision::keep;
    if (decision[f] == Decision::keep || decision[f] == Decision::reverse) {
      const bool canonical = (decision[f] == Decision::reverse) == (patches.reversed[f] != 0);
      const double area = norm(face_normal_unnormalized(mesh, mesh.faces[f]));
      (canonical ? agree : disagree)[patches.patch_of_face[f]] += area;
    }
  }
  OrientResult out;
  out.mesh = mesh;
  for (std::size_t f = 0; f < n; ++f) {
    bool reverse = decision[f] == Decision::reverse;
    if (decision[f] == Decision::both_sides) ++out.seen_from_both_sides;
    if (decision[f] == Decision::unseen) {
      ++out.never_seen;
      const std::uint32_t p = patches.patch_of_face[f];
      // Closed: outward is known. Open: as most of its seen area is wound (canonical on a tie).
      const bool canonical = patches.closed[p] || agree[p] >= disagree[p];
      reverse = canonical == (patches.reversed[f] != 0);
      if (!patches.closed[p] && agree[p] == 0 && disagree[p] == 0) reverse = false;  // nothing to go by
    }
    if (reverse) {
      std::swap(out.mesh.faces[f][1], out.mesh.faces[f][2]);
      ++out.reversed;
    }
  }
  return out;
}

}  // namespace visimp
