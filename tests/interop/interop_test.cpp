// The OpenMesh and CGAL adapters (visimp/interop/*.h): exact round trips, the V property,
// refusal of what the half-edge structures cannot hold, and simplification in place giving
// exactly what visimp::simplify gives on the same mesh.
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <gtest/gtest.h>

#include "test_meshes.h"
#include "visimp/cameras/camera_set.h"
#include "visimp/interop/cgal.h"
#include "visimp/interop/openmesh.h"
#include "visimp/io/mesh_io.h"
#include "visimp/render/renderer.h"
#include "visimp/visibility/visibility.h"

namespace visimp {
namespace {

struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using TriMeshD = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;
using TriMeshF = OpenMesh::TriMesh_ArrayKernelT<>;
using PolyMeshD = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;
using SurfaceMesh = CGAL::Surface_mesh<CGAL::Simple_cartesian<double>::Point_3>;
using ExactSurfaceMesh = CGAL::Surface_mesh<CGAL::Exact_predicates_exact_constructions_kernel::Point_3>;

Mesh bunny() { return read_mesh(test::bundled_mesh("bunny.ply")); }

void expect_same(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.num_vertices(), b.num_vertices());
  ASSERT_EQ(a.num_faces(), b.num_faces());
  for (std::size_t v = 0; v < a.num_vertices(); ++v) {
    EXPECT_EQ(a.positions[v].x, b.positions[v].x);
    EXPECT_EQ(a.positions[v].y, b.positions[v].y);
    EXPECT_EQ(a.positions[v].z, b.positions[v].z);
  }
  for (std::size_t f = 0; f < a.num_faces(); ++f) EXPECT_EQ(a.faces[f], b.faces[f]) << f;
}

std::vector<float> bunny_visibility(const Mesh& mesh) {
  RenderOptions render;
  render.resolution = 128;
  auto renderer = make_raster_renderer(render);
  return compute_visibility(mesh, octahedron_cameras(1), *renderer).face;
}

// visimp's own VG run on `in` with V as its face quality: what simplify_in_place must equal.
Simplified visimp_vg(Mesh in, const std::vector<float>& v, SimplifyOptions options) {
  options.face_visibility = v;
  in.face_quality = v;
  return simplify(in, options);
}

// Three triangles on one edge: neither structure can hold the third.
Mesh fin() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

TEST(OpenMeshAdapter, RoundTripsExactlyWithDoublePoints) {
  const Mesh in = bunny();
  TriMeshD om;
  interop::to_openmesh(in, om);
  EXPECT_EQ(om.n_faces(), in.num_faces());
  expect_same(interop::from_openmesh(om), in);
  // Float points round to float, nothing else changes.
  TriMeshF omf;
  interop::to_openmesh(in, omf);
  const Mesh back = interop::from_openmesh(omf);
  ASSERT_EQ(back.num_faces(), in.num_faces());
  for (std::size_t v = 0; v < in.num_vertices(); ++v)
    EXPECT_EQ(back.positions[v].x, static_cast<double>(static_cast<float>(in.positions[v].x)));
}

TEST(OpenMeshAdapter, FansPolygonsAndSkipsDeletedElements) {
  PolyMeshD pm;
  std::vector<PolyMeshD::VertexHandle> v;
  for (int i = 0; i < 5; ++i) v.push_back(pm.add_vertex(PolyMeshD::Point(i, i * i, 0)));
  pm.add_face(std::vector<PolyMeshD::VertexHandle>{v[0], v[1], v[2], v[3]});
  const Mesh quad = interop::from_openmesh(pm);
  ASSERT_EQ(quad.num_faces(), 2u);
  EXPECT_EQ(quad.faces[0], (Face{0, 1, 2}));
  EXPECT_EQ(quad.faces[1], (Face{0, 2, 3}));
  EXPECT_EQ(quad.num_vertices(), 5u);  // the isolated vertex stays

  TriMeshD om;
  interop::to_openmesh(bunny(), om);
  om.request_face_status();
  om.request_edge_status();
  om.request_vertex_status();
  const std::size_t faces = om.n_faces();
  om.delete_face(om.face_handle(0), true);
  const Mesh pruned = interop::from_openmesh(om);
  EXPECT_EQ(pruned.num_faces(), faces - 1);
  for (const Face& f : pruned.faces)
    for (VertexIndex i : f) EXPECT_LT(i, pruned.num_vertices());
}

TEST(OpenMeshAdapter, RefusesWhatItCannotHoldAndSaysSo) {
  TriMeshD om;
  EXPECT_THROW(interop::to_openmesh(fin(), om), InvalidMeshError);
  std::size_t refused = 99;
  interop::to_openmesh(fin(), om, &refused);
  EXPECT_EQ(refused, 1u);
  EXPECT_EQ(om.n_faces(), 2u);
}

TEST(OpenMeshAdapter, CarriesVisibilityAndSimplifiesInPlaceLikeVisimp) {
  const Mesh in = bunny();
  const std::vector<float> v = bunny_visibility(in);
  TriMeshD om;
  interop::to_openmesh(in, om);
  interop::set_visibility_property(om, v);
  EXPECT_THROW(interop::set_visibility_property(om, std::vector<float>(3, 1.f)), UsageError);
  const Mesh with_v = interop::from_openmesh(om);
  ASSERT_EQ(with_v.face_quality, v);

  SimplifyOptions options;
  options.target_ratio = 0.25;
  options.method = SimplifyMethod::vg;
  const SimplifyResult result = interop::simplify_in_place(om, options);
  // The same as visimp's own VG run on the same mesh and V, face for face.
  const Simplified reference = visimp_vg(in, v, options);
  EXPECT_EQ(result.faces_out, reference.mesh.num_faces());
  const Mesh out = interop::from_openmesh(om);
  expect_same(out, reference.mesh);
  EXPECT_EQ(out.face_quality, reference.mesh.face_quality);  // survivors keep their V

  TriMeshD no_v;
  interop::to_openmesh(in, no_v);
  EXPECT_THROW(interop::simplify_in_place(no_v, options), UsageError);
  options.method = SimplifyMethod::qb;
  EXPECT_LE(interop::simplify_in_place(no_v, options).faces_out, in.num_faces() / 4 + 1);
}

TEST(CgalAdapter, RoundTripsExactlyAndRefusesComplexEdges) {
  const Mesh in = bunny();
  SurfaceMesh sm;
  interop::to_cgal(in, sm);
  EXPECT_EQ(sm.number_of_faces(), in.num_faces());
  expect_same(interop::from_cgal(sm), in);
  ExactSurfaceMesh exact;
  interop::to_cgal(in, exact);
  expect_same(interop::from_cgal(exact), in);  // doubles are exact in an exact kernel

  EXPECT_THROW(interop::to_cgal(fin(), sm), InvalidMeshError);
  std::size_t refused = 99;
  interop::to_cgal(fin(), sm, &refused);
  EXPECT_EQ(refused, 1u);
  EXPECT_EQ(sm.number_of_faces(), 2u);

  // Removed faces are skipped, indices compacted.
  interop::to_cgal(in, sm);
  CGAL::Euler::remove_face(sm.halfedge(*sm.faces().begin()), sm);
  const Mesh pruned = interop::from_cgal(sm);
  EXPECT_EQ(pruned.num_faces(), in.num_faces() - 1);
  for (const Face& f : pruned.faces)
    for (VertexIndex i : f) EXPECT_LT(i, pruned.num_vertices());
}

TEST(CgalAdapter, CarriesVisibilityAndSimplifiesInPlaceLikeVisimp) {
  const Mesh in = bunny();
  const std::vector<float> v = bunny_visibility(in);
  SurfaceMesh sm;
  interop::to_cgal(in, sm);
  interop::set_visibility_map(sm, v);
  EXPECT_THROW(interop::set_visibility_map(sm, std::vector<float>(3, 1.f)), UsageError);
  ASSERT_EQ(interop::from_cgal(sm).face_quality, v);

  SimplifyOptions options;
  options.target_ratio = 0.25;
  options.method = SimplifyMethod::vg;
  interop::simplify_in_place(sm, options);
  const Simplified reference = visimp_vg(in, v, options);
  const Mesh out = interop::from_cgal(sm);
  expect_same(out, reference.mesh);
  EXPECT_EQ(out.face_quality, reference.mesh.face_quality);
  EXPECT_TRUE(sm.is_valid(false));
}

}  // namespace
}  // namespace visimp
