// visimp scene park / info: walkthrough scenes (docs/cells.md).
#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "cli.h"
#include "commands.h"
#include "visimp/cells/scene.h"
#include "visimp/core/bounding_box.h"
#include "visimp/core/errors.h"
#include "visimp/report/json.h"

namespace visimp::app {
namespace {

constexpr const char* kSceneUsage =
    "usage: visimp scene park|info ...\n"
    "\n"
    "  park -o SCENE.json [--objects N] [--area W,D]   meshes placed at random on the x-y plane\n"
    "  info SCENE                                      objects, meshes, faces and extent of a scene\n"
    "\n"
    "'visimp scene COMMAND --help' describes each.\n";

// The bundled meshes, and the shared ones when ../shared is there; KiCad parts are Z-up.
std::vector<std::string> default_park_meshes() {
  std::vector<std::string> out;
  for (const char* name : {"bunny.ply", "teapot.ply", "fandisk_cad.ply", "kicad_esp_wroom02.ply"})
    out.push_back(std::string(VISIMP_MESHES_DIR) + "/" + name);
  for (const char* name : {"dragon.ply", "kicad_dsub62_male.ply", "kicad_cap_snapin_d40.ply"}) {
    const std::string path = std::string(VISIMP_SHARED_MESHES_DIR) + "/" + name;
    if (std::filesystem::exists(path)) out.push_back(path);
  }
  return out;
}

int run_park(const Args& args) {
  ParkOptions options;
  std::string out, area, meshes_text;
  bool json_out = false;
  ArgParser parser(
      "visimp scene park -o SCENE.json [--objects N | --faces F] [--area W,D] [--object-size S] [--seed S] "
      "[--meshes F,F:z,..]",
      "Places N meshes at random on distinct spots of a jittered grid over W x D of the x-y plane,\n"
      "each scaled to a bounding diagonal of S x U(0.8, 1.2), stood upright on z = 0 and turned about\n"
      "z (the statuary parks of the walkthrough-LOD paper). Meshes default to the bundled ones and,\n"
      "when ../shared is present, the dragon and the KiCad parts; in --meshes a ':z' suffix marks a\n"
      "Z-up mesh (the others are taken as Y-up). Writes the scene JSON (docs/cells.md).",
      0, 0);
  parser.add(option_spec("-o", "SCENE.json", out, "the scene file"));
  parser.add(option_spec("--objects", "N", options.objects, "objects to place"));
  parser.add(option_spec("--faces", "F", options.faces, "instead of --objects: place objects until F faces"));
  parser.add(option_spec("--area", "W,D", area, "extent of the park along x and y (default 200,200)"));
  parser.add(option_spec("--object-size", "S", options.object_size, "typical bounding diagonal of an object"));
  parser.add(option_spec("--seed", "S", options.seed, "seed of the placement"));
  parser.add(option_spec("--meshes", "F,F:z,..", meshes_text, "meshes to place (':z' = Z-up)"));
  parser.add(switch_spec("--json", json_out, "machine-readable summary"));
  if (!parser.parse(args)) return 0;
  if (out.empty()) throw UsageError("-o SCENE.json is required");
  if (!area.empty()) {
    const auto comma = area.find(',');
    if (comma == std::string::npos) throw UsageError("--area expects W,D, got '" + area + "'");
    options.width = parse_double(area.substr(0, comma), "--area");
    options.depth = parse_double(area.substr(comma + 1), "--area");
  }
  if (options.objects == 0 || options.objects > 1000000) throw UsageError("--objects must be in [1, 1000000]");
  if (options.faces > 4000000000u) throw UsageError("--faces must be at most 4e9");
  if (!(options.width > 0) || !(options.depth > 0) || !std::isfinite(options.width * options.depth))
    throw UsageError("--area must be two positive finite sizes");
  if (!(options.object_size > 0) || !std::isfinite(options.object_size))
    throw UsageError("--object-size must be positive and finite");
  std::vector<std::string> meshes;
  std::vector<bool> z_up;
  if (meshes_text.empty()) {
    for (const std::string& m : default_park_meshes()) {
      meshes.push_back(m);
      z_up.push_back(std::filesystem::path(m).filename().string().rfind("kicad_", 0) == 0);
    }
  } else {
    std::stringstream in(meshes_text);
    for (std::string part; std::getline(in, part, ',');) {
      const bool z = part.size() > 2 && part.compare(part.size() - 2, 2, ":z") == 0;
      meshes.push_back(z ? part.substr(0, part.size() - 2) : part);
      z_up.push_back(z);
    }
  }
  const Scene scene = make_park(meshes, z_up, options);
  write_scene(scene, out);
  if (json_out) {
    JsonWriter json(std::cout);
    json.begin_object().field("command", "scene park").field("output", out);
    json.field("objects", scene.objects.size()).field("meshes", scene.meshes.size()).field("faces", scene.face_count());
    json.end_object();
    std::cout << '\n';
  } else {
    std::cout << out << ": " << scene.objects.size() << " objects from " << scene.meshes.size() << " meshes, "
              << scene.face_count() << " faces\n";
  }
  return 0;
}

int run_scene_info(const Args& args) {
  bool json_out = false;
  ArgParser parser("visimp scene info SCENE [--json]",
                   "Reads a scene (JSON, or a mesh whose components are the objects) and prints its objects,\n"
                   "meshes, faces and bounding box.",
                   1, 1);
  parser.add(switch_spec("--json", json_out, "machine-readable summary"));
  if (!parser.parse(args)) return 0;
  const std::string& in = parser.positionals()[0];
  const Scene scene = read_scene(in);
  BoundingBox box;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const Mesh m = scene.object_mesh(i);
    for (const Face& f : m.faces)
      for (VertexIndex v : f) box.extend(m.positions[v]);
  }
  if (json_out) {
    JsonWriter json(std::cout);
    json.begin_object().field("command", "scene info").field("input", in);
    json.field("objects", scene.objects.size()).field("meshes", scene.meshes.size()).field("faces", scene.face_count());
    json.key("bbox").begin_object();
    json.key("min").begin_array().value(box.min.x).value(box.min.y).value(box.min.z).end_array();
    json.key("max").begin_array().value(box.max.x).value(box.max.y).value(box.max.z).end_array();
    json.end_object().end_object();
    std::cout << '\n';
  } else {
    std::cout << in << ": " << scene.objects.size() << " objects, " << scene.meshes.size() << " meshes, "
              << scene.face_count() << " faces\n";
  }
  return 0;
}

}  // namespace

int run_scene(const Args& args) {
  if (args.empty() || args[0] == "--help" || args[0] == "-h") {
    (args.empty() ? std::cerr : std::cout) << kSceneUsage;
    return args.empty() ? 2 : 0;
  }
  const Args rest(args.begin() + 1, args.end());
  if (args[0] == "park") return run_park(rest);
  if (args[0] == "info") return run_scene_info(rest);
  throw UsageError("unknown scene command '" + args[0] + "' (park or info)");
}

}  // namespace visimp::app
