// Makes the large smooth meshes of the speed benchmarks (docs/bench.md): Loop subdivision
// (OpenMesh's LoopT, a bench-only dependency) of a mesh, a given number of times. Each round
// quadruples the faces: the shared dragon (871,306 faces) gives 3,485,224 after one round and
// 13,940,896 after two. The subdivided vertices come after the original ones, as a subdivider
// emits them — a vertex order with little locality, as large meshes from other tools have.
//
// usage: make_subdivided IN ROUNDS OUT    (OUT: binary PLY, written atomically)
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Subdivider/Uniform/LoopT.hh>

#include <cstdio>
#include <string>
#include <vector>

#include "bench_main.h"
#include "visimp/interop/openmesh.h"
#include "visimp/io/mesh_io.h"

namespace {

constexpr const char* kUsage = "usage: make_subdivided IN ROUNDS OUT   Loop subdivision, ROUNDS times (1..3)\n";

int run(const std::vector<std::string>& args) {
  if (args.size() != 3) throw visimp::UsageError("make_subdivided takes IN ROUNDS OUT (see --help)");
  const int rounds = std::stoi(args[1]);
  if (rounds < 1 || rounds > 3) throw visimp::UsageError("ROUNDS must be 1, 2 or 3");
  using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;
  OMesh om;
  visimp::interop::to_openmesh(visimp::read_mesh(args[0]), om);
  OpenMesh::Subdivider::Uniform::LoopT<OMesh> loop;
  loop.attach(om);
  loop(static_cast<std::size_t>(rounds));
  loop.detach();
  const visimp::Mesh out = visimp::interop::from_openmesh(om);
  visimp::write_mesh(out, args[2]);
  std::fprintf(stderr, "%s: %zu faces, %zu vertices\n", args[2].c_str(), out.num_faces(), out.num_vertices());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return bench::guarded_main("make_subdivided", kUsage, argc, argv, run); }
