#include <iostream>
#include <optional>

#include "backends.h"
#include "cli.h"
#include "commands.h"
#include "visimp/core/mesh_stats.h"
#include "visimp/report/json.h"
#include "visimp/visibility/visibility.h"

namespace visimp::app {

int run_info(const Args& args) {
  StreamOptions stream;
  // Winding as the cameras see it, coarsely: info must stay quick on big meshes.
  SamplingOptions sampling;
  sampling.cameras = "66";
  sampling.resolution = 256;
  bool skip_visibility = false;
  ArgParser parser("visimp info IN [--json] [--no-visibility]",
                   "Reports counts, bounding box, components, boundary and non-manifold edges,\n"
                   "non-manifold vertices, misoriented edges, degenerate and duplicate faces, and\n"
                   "(from a quick visibility pass, 66 cameras at 256² unless told otherwise) how many\n"
                   "faces are seen mainly from behind: wound inward ('visimp orient' repairs them).",
                   1);
  parser.add(describe_options(sampling));
  parser.add(switch_spec("--no-visibility", skip_visibility, "skip the visibility pass (counts only)"));
  parser.add(describe_options(stream, false));
  if (!parser.parse(args)) return 0;
  const std::string& in = parser.positionals()[0];
  const Mesh mesh = read_input(in, stream);
  const MeshStats s = analyze(mesh);
  std::optional<Visibility> v;
  if (!skip_visibility && mesh.num_faces() > 0) {
    const auto renderer = make_renderer(sampling.backend, render_options(sampling));
    v = compute_visibility(mesh, camera_set_from_spec(sampling.cameras), *renderer);
  }
  if (stream.json) {
    JsonWriter json(std::cout);
    json.begin_object()
        .field("file", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("vertices", s.vertices)
        .field("faces", s.faces)
        .field("edges", s.edges)
        .field("components", s.components)
        .field("isolated_vertices", s.isolated_vertices)
        .field("boundary_edges", s.boundary_edges)
        .field("non_manifold_edges", s.non_manifold_edges)
        .field("non_manifold_vertices", s.non_manifold_vertices)
        .field("misoriented_edges", s.misoriented_edges)
        .field("degenerate_faces", s.degenerate_faces)
        .field("duplicate_faces", s.duplicate_faces)
        .field("closed_manifold", s.closed_manifold())
        .field("area", s.area)
        .field("has_vertex_quality", mesh.has_vertex_quality())
        .field("has_face_quality", mesh.has_face_quality());
    if (v) {
      json.key("visibility")
          .begin_object()
          .field("cameras", v->stats.cameras)
          .field("resolution", static_cast<std::int64_t>(v->stats.resolution))
          .field("mesh_visibility", v->mesh)
          .field("hidden_area_fraction", v->stats.hidden_area_fraction)
          .field("seen_from_behind_faces", v->stats.seen_from_behind)
          .field("two_sided_faces", v->stats.two_sided_faces)
          .end_object();
    }
    json.key("bbox").begin_object();
    json.key("min").begin_array().value(s.bbox.min.x).value(s.bbox.min.y).value(s.bbox.min.z).end_array();
    json.key("max").begin_array().value(s.bbox.max.x).value(s.bbox.max.y).value(s.bbox.max.z).end_array();
    json.field("diagonal", s.bbox.diagonal()).end_object();
    json.end_object();
    return 0;
  }
  std::cout << in << "\n"
            << "  vertices              " << s.vertices << " (" << s.isolated_vertices << " isolated)\n"
            << "  faces                 " << s.faces << " (" << s.degenerate_faces << " degenerate, "
            << s.duplicate_faces << " duplicate)\n"
            << "  edges                 " << s.edges << " (" << s.boundary_edges << " boundary, "
            << s.non_manifold_edges << " non-manifold, " << s.misoriented_edges << " misoriented)\n"
            << "  non-manifold vertices " << s.non_manifold_vertices << "\n"
            << "  components            " << s.components << "\n"
            << "  closed 2-manifold     " << (s.closed_manifold() ? "yes" : "no") << "\n"
            << "  area                  " << s.area << "\n"
            << "  bbox                  [" << s.bbox.min.x << ", " << s.bbox.min.y << ", " << s.bbox.min.z << "] - ["
            << s.bbox.max.x << ", " << s.bbox.max.y << ", " << s.bbox.max.z << "], diagonal " << s.bbox.diagonal()
            << "\n"
            << "  quality               " << (mesh.has_vertex_quality() ? "vertex " : "")
            << (mesh.has_face_quality() ? "face" : "")
            << (mesh.has_vertex_quality() || mesh.has_face_quality() ? "" : "none") << "\n";
  if (v) {
    std::cout << "  seen from behind      " << v->stats.seen_from_behind << " faces (V(M) " << v->mesh << ", "
              << v->stats.cameras << " cameras at " << v->stats.resolution << "²; 'visimp orient' rewinds them)\n";
  }
  return 0;
}

}  // namespace visimp::app
