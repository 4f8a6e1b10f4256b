// Links one module target (visimp::simplify) and nothing else of visimp.
#include <cstdio>

#include "visimp/simplify/simplify.h"

int main() {
  visimp::Mesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0}};
  quad.faces = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  visimp::SimplifyOptions options;
  options.target_faces = 2;
  const visimp::Simplified s = visimp::simplify(quad, options);
  std::printf("%zu\n", s.mesh.num_faces());
  return s.mesh.num_faces() == 2 ? 0 : 1;
}
