#include <chrono>
#include <iostream>

#include "cli.h"
#include "commands.h"
#include "visimp/core/bounding_box.h"
#include "visimp/report/json.h"

namespace visimp::app {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}
}  // namespace

int run_simplify(const Args& args) {
  SimplifyOptions options;
  StreamOptions stream;
  ArgParser parser("visimp simplify IN OUT (--target N | --ratio R | --max-error E) [options]",
                   "Simplifies IN by quadric edge collapse (Garland-Heckbert, plain quadrics: QB) and\n"
                   "writes OUT atomically. Non-manifold and misoriented parts are kept, locked.",
                   2);
  parser.add(describe_options(options));
  parser.add(describe_options(stream, true));
  if (!parser.parse(args)) return 0;
  check_options(options);
  const std::string& in = parser.positionals()[0];
  const std::string& out = parser.positionals()[1];

  auto t = std::chrono::steady_clock::now();
  const Mesh mesh = read_input(in, stream);
  const double read_seconds = seconds_since(t);

  ProgressBar progress("simplify");
  Simplified simplified = simplify(mesh, options, &progress);

  t = std::chrono::steady_clock::now();
  write_output(simplified.mesh, out, in, stream);
  const double write_seconds = seconds_since(t);

  const SimplifyResult& r = simplified.result;
  const double diagonal = bounding_box(mesh).diagonal();
  std::ostream& report = out == "-" ? std::cerr : std::cout;
  if (stream.json) {
    JsonWriter json(report);
    json.begin_object()
        .field("command", "simplify")
        .field("input", in)
        .field("output", out)
        .field("method", "qb")
        .field("faces_in", r.faces_in)
        .field("faces_out", r.faces_out)
        .field("vertices_in", r.vertices_in)
        .field("vertices_out", r.vertices_out)
        .field("target_faces", r.target_faces)
        .field("collapses", r.collapses)
        .field("rejected_collapses", r.rejected_collapses)
        .field("locked_vertices", r.locked_vertices)
        .field("dropped_faces", r.dropped_faces)
        .field("stop_reason", to_string(r.stop_reason))
        .field("max_error_relative", r.max_error)
        .field("max_error", r.max_error * diagonal)
        .field("bbox_diagonal", diagonal);
    json.key("seconds").begin_object()
        .field("read", read_seconds)
        .field("simplify", r.seconds)
        .field("write", write_seconds)
        .end_object();
    json.end_object();
  } else {
    report << in << ": " << r.faces_in << " -> " << r.faces_out << " faces (" << to_string(r.stop_reason)
           << "), max error " << r.max_error << " of the bbox diagonal, " << r.seconds << " s\n";
  }
  return 0;
}

}  // namespace visimp::app
