#include <iostream>

#include "cli.h"
#include "commands.h"
#include "visimp/report/json.h"

namespace visimp::app {

int run_convert(const Args& args) {
  StreamOptions stream;
  ArgParser parser("visimp convert IN OUT [options]",
                   "Converts between PLY, OBJ, OFF and STL (formats from the extensions or the\n"
                   "--*format options). Polygons are fan-triangulated; see docs/formats.md for\n"
                   "what each format keeps.",
                   2);
  parser.allow_output_flag(1);
  parser.add(describe_options(stream, true));
  if (!parser.parse(args)) return 0;
  const std::string& in = parser.positionals()[0];
  const std::string& out = parser.positionals()[1];
  const Mesh mesh = read_input(in, stream);
  write_output(mesh, out, in, stream);
  if (stream.json) {
    JsonWriter json(out == "-" ? std::cerr : std::cout);
    json.begin_object()
        .field("command", "convert")
        .field("input", in)
        .field("input_format", input_format_name(stream))
        .field("format_detected", input_format_detected(stream))
        .field("output", out)
        .field("vertices", mesh.num_vertices())
        .field("faces", mesh.num_faces())
        .end_object();
  }
  return 0;
}

}  // namespace visimp::app
