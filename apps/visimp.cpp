// visimp: the command-line front end. Thin by design: parse, call the library, report.
#include <cstring>
#include <exception>
#include <iostream>
#include <new>

#include "cli.h"
#include "commands.h"
#include "visimp/core/errors.h"
#include "visimp/io/interrupt_cleanup.h"

namespace {

constexpr const char* kUsage =
    "usage: visimp COMMAND [options]\n"
    "\n"
    "commands:\n"
    "  compare IN [-o DIR]        QB vs VG at the same face counts: errors, seconds, plots, report.html\n"
    "  simplify IN OUT            quadric edge collapse, plain (QB) or visibility-guided (VG)\n"
    "  info IN                    counts, bounding box, components, boundary and non-manifold edges\n"
    "  convert IN OUT             change mesh format (ply, obj, off, stl)\n"
    "  visibility IN OUT.ply      per-face visibility V(t) from a sphere of cameras (Zhang & Turk)\n"
    "  visibility-merge PART...   add tallies of camera slices computed separately\n"
    "  orient IN OUT              wind every face outward, as the cameras see it\n"
    "  visibility-study IN        visibility error vs cameras and seconds (the paper's Fig. 3)\n"
    "  metro A B                  sampled surface distances both ways: Hausdorff, mean, RMS, histogram\n"
    "  imgerr A B                 image RMS error over 20 flat-shaded views (Zhang & Turk eq. 5.11)\n"
    "  patches build|query|study  patch bitfields and view reconstruction from the same sampling\n"
    "  field build|query|study    the visibility field: cell ids on two-plane slabs, resampled per view\n"
    "  scene park|info            walkthrough scenes: meshes placed by transforms (statuary parks)\n"
    "  cells build|walk           walkthrough LOD per hexagonal cell (SVMesh/MVMesh), PSNR along a path\n"
    "\n"
    "'visimp COMMAND --help' describes each command; 'visimp --version' prints the version.\n"
    "exit codes: 0 success, 1 bad input or I/O failure, 2 bad usage, 3 internal error\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace visimp;
  using namespace visimp::app;
  if (argc < 2) {
    std::cerr << kUsage;
    return kExitBadUsage;
  }
  const std::string command = argv[1];
  const app::Args args(argv + 2, argv + argc);
  install_interrupt_cleanup();  // no temporary file outlives a Ctrl-C, a kill or a hang-up
  return run_reporting_errors("visimp " + command, [&] {
    if (command == "--help" || command == "-h" || command == "help") {
      std::cout << kUsage;
      return int(kExitSuccess);
    }
    if (command == "--version") {
      std::cout << app::version_line() << "\n";
      return int(kExitSuccess);
    }
    if (command == "simplify") return app::run_simplify(args);
    if (command == "info") return app::run_info(args);
    if (command == "convert") return app::run_convert(args);
    if (command == "visibility") return app::run_visibility(args);
    if (command == "visibility-merge") return app::run_visibility_merge(args);
    if (command == "orient") return app::run_orient(args);
    if (command == "visibility-study") return app::run_visibility_study(args);
    if (command == "metro") return app::run_metro(args);
    if (command == "imgerr") return app::run_imgerr(args);
    if (command == "compare") return app::run_compare(args);
    if (command == "patches") return app::run_patches(args);
    if (command == "field") return app::run_field(args);
    if (command == "scene") return app::run_scene(args);
    if (command == "cells") return app::run_cells(args);
    throw UsageError("unknown command '" + command + "' (see visimp --help)");
  });
}
