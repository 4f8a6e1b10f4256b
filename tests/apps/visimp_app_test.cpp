// End-to-end: the `visimp` binary's exit codes, messages, streams and outputs.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <utility>

#include "app_runner.h"
#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/io/mesh_io.h"
#include "visimp/simplify/simplify.h"

namespace visimp {
namespace {

using test::AppRun;
using test::run;

class App : public ::testing::Test {
 protected:
  // Each test's outputs live in its own directory, removed when the fixture is destroyed.
  const test::TempDir temp{::testing::UnitTest::GetInstance()->current_test_info()->name()};
  const std::string dir = temp.path(), bunny = test::bundled_mesh("bunny.ply");
};

TEST_F(App, HelpEverywhereExitsZero) {
  for (const char* cmd : {"--help",
                          "simplify --help",
                          "info --help",
                          "convert --help",
                          "visibility --help",
                          "visibility-merge --help",
                          "visibility-study --help",
                          "orient --help",
                          "metro --help",
                          "imgerr --help",
                          "compare --help",
                          "patches --help",
                          "patches build --help",
                          "patches query --help",
                          "patches study --help",
                          "field --help",
                          "field build --help",
                          "field query --help",
                          "field study --help",
                          "scene --help",
                          "scene park --help",
                          "scene info --help",
                          "cells --help",
                          "cells build --help",
                          "cells walk --help"}) {
    const AppRun r = run(cmd, dir);
    EXPECT_EQ(r.code, 0) << cmd;
    EXPECT_NE(r.out.find("usage: visimp"), std::string::npos) << cmd;
  }
  // Defaults in the help come from SimplifyOptions.
  EXPECT_NE(run("simplify --help", dir).out.find("--max-normal-change DEG"), std::string::npos);
}

TEST_F(App, SimplifyWritesTheTargetAndAJsonSummary) {
  const AppRun r = run("simplify " + bunny + " " + dir + "/out.ply --ratio 0.1 --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"target_faces\": 367"), std::string::npos) << r.out;  // round(0.1 × 3674)
  EXPECT_NE(r.out.find("\"faces_out\": 366"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"stop_reason\": \"target_reached\""), std::string::npos);
  EXPECT_EQ(read_mesh(dir + "/out.ply").num_faces(), 366u);  // closed: 367 is odd, so one below
  // The plane weights it ran with, so two summaries say whether they weighed faces alike.
  EXPECT_NE(r.out.find("\"quadric_weights\": \"area\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"area_floor\": 0"), std::string::npos) << r.out;
  const AppRun floor = run("simplify " + bunny + " " + dir + "/floor.ply --ratio 0.1 --area-floor 1 --json", dir);
  ASSERT_EQ(floor.code, 0) << floor.err;
  EXPECT_NE(floor.out.find("\"area_floor\": 1"), std::string::npos) << floor.out;
}

// simplify's and visibility's JSON summaries record every option the result depends on, typed, so that a pipeline
// can tell two runs apart or redo one; the sampling options only when V was rendered.
TEST_F(App, JsonSummariesRecordEveryOptionTheyRanWith) {
  // The "options" object of a summary (flat: its values hold no braces).
  auto options_of = [](const std::string& out) {
    const std::size_t at = out.find("\"options\": {");
    return at == std::string::npos ? std::string() : out.substr(at, out.find('}', at) - at);
  };
  const AppRun qb = run("simplify " + bunny + " " + dir + "/qb.ply --ratio 0.2 --no-folds --max-normal-change 120 " +
                            "--boundary-weight 5 --json",
                        dir);
  ASSERT_EQ(qb.code, 0) << qb.err;
  const std::string qb_options = options_of(qb.out);
  for (const char* field : {"\"ratio\": 0.2", "\"target\": 0", "\"max_error\": null", "\"no_folds\": true",
                            "\"freeze_boundary\": false", "\"max_normal_change\": 120", "\"boundary_weight\": 5",
                            "\"quadric_weights\": \"area\"", "\"method\": \"qb\""})
    EXPECT_NE(qb_options.find(field), std::string::npos) << field << "\n" << qb.out;
  SimplifyOptions defaults;
  for (const OptionSpec& spec : describe_options(defaults)) {  // every simplify option, named as its flag
    std::string key = spec.flag.substr(2);
    std::replace(key.begin(), key.end(), '-', '_');
    EXPECT_NE(qb_options.find("\"" + key + "\": "), std::string::npos) << key;
  }
  EXPECT_EQ(qb_options.find("\"cameras\""), std::string::npos) << "nothing was rendered";

  const AppRun vg = run("simplify " + bunny + " " + dir + "/vg.ply --ratio 0.2 --method vg --cameras 6 " +
                            "--resolution 64 --no-refine --json",
                        dir);
  ASSERT_EQ(vg.code, 0) << vg.err;
  for (const char* field : {"\"method\": \"vg\"", "\"cameras\": \"6\"", "\"resolution\": 64", "\"no_refine\": true",
                            "\"backend\": \"raster\"", "\"no_folds\": false"})
    EXPECT_NE(options_of(vg.out).find(field), std::string::npos) << field << "\n" << vg.out;

  const AppRun v = run("visibility " + bunny + " " + dir + "/v.ply --cameras 18 --resolution 96 --depth-tolerance 0.5 --json",
                       dir);
  ASSERT_EQ(v.code, 0) << v.err;
  for (const char* field : {"\"cameras\": \"18\"", "\"resolution\": 96", "\"depth_tolerance\": 0.5",
                            "\"trust_winding\": false", "\"worst_view_cosine\": 0.25"})
    EXPECT_NE(options_of(v.out).find(field), std::string::npos) << field << "\n" << v.out;
}

TEST_F(App, UsageErrorsExitTwoWithOneLine) {
  for (const char* args : {"simplify a.ply", "simplify a.ply b.ply --bogus", "simplify a.ply b.ply",
                           "simplify a.ply b.ply --ratio x", "frobnicate"}) {
    const AppRun r = run(args, dir);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  // Out-of-range sampling is refused up front, naming the flag, before any work or output.
  const std::pair<std::string, const char*> sampling[] = {
      {"imgerr " + bunny + " " + bunny + " --supersample 0", "--supersample"},
      {"compare " + bunny + " -o " + dir + "/cmp --image-supersample 9", "--image-supersample"},
      {"compare " + bunny + " -o " + dir + "/cmp --tie-noise 101", "--tie-noise"}};
  for (const auto& [args, flag] : sampling) {
    const AppRun r = run(args, dir);
    EXPECT_EQ(r.code, 2) << args;
    EXPECT_NE(r.err.find(flag), std::string::npos) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/cmp"));
}

TEST_F(App, BadInputExitsOneNamingTheFileAndWritesNothing) {
  const std::string bad = dir + "/bad.ply";
  std::ofstream(bad) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n";
  const std::string out = dir + "/out.ply";
  const AppRun r = run("simplify " + bad + " " + out + " --ratio 0.5", dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("bad.ply"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  const AppRun missing = run("info " + dir + "/nope.obj", dir);
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.err.find("nope.obj"), std::string::npos);
}

TEST_F(App, RefusesToOverwriteTheInput) {
  const std::string copy = dir + "/in.ply";
  std::filesystem::copy_file(bunny, copy);
  const auto before = std::filesystem::file_size(copy);
  const AppRun r = run("simplify " + copy + " " + copy + " --ratio 0.5", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--in-place"), std::string::npos);
  EXPECT_EQ(std::filesystem::file_size(copy), before);
  EXPECT_EQ(run("simplify " + copy + " " + copy + " --ratio 0.5 --in-place", dir).code, 0);
  EXPECT_EQ(read_mesh(copy).num_faces(), 1836u);  // 3674/2 rounded, minus the odd face
}

TEST_F(App, PipesThroughStdinAndStdout) {
  const std::string out = dir + "/piped.obj";
  const AppRun r = run("simplify - - --ratio 0.5 --format ply --output-format obj --json", dir, bunny);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\nf "), std::string::npos);           // the mesh went to stdout
  EXPECT_NE(r.err.find("\"faces_out\""), std::string::npos);  // the summary to stderr
  std::ofstream(out) << r.out;
  EXPECT_EQ(read_mesh(out).num_faces(), 1836u);
}

TEST_F(App, TheContentDecidesWhenTheExtensionIsMissingOrWrong) {
  // An OBJ named .ply, a PLY without extension, a PLY on stdin without --format.
  ASSERT_EQ(run("convert " + bunny + " " + dir + "/bunny.obj", dir).code, 0);
  std::filesystem::copy_file(dir + "/bunny.obj", dir + "/obj_in_disguise.ply");
  std::filesystem::copy_file(bunny, dir + "/bunny_no_extension");
  for (const std::string& in : {dir + "/obj_in_disguise.ply", dir + "/bunny_no_extension"}) {
    const AppRun r = run("simplify " + in + " " + dir + "/out.ply --ratio 0.5 --json", dir);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\"format_detected\": true"), std::string::npos) << r.out;
    EXPECT_EQ(r.err, "");
  }
  const AppRun named = run("info " + bunny + " --no-visibility --json", dir);
  EXPECT_NE(named.out.find("\"format_detected\": false"), std::string::npos) << named.out;
  EXPECT_NE(named.out.find("\"input_format\": \"ply\""), std::string::npos) << named.out;
  // stdin without --format, stdout in the input's format (OBJ in, OBJ out).
  const AppRun piped = run("simplify - - --ratio 0.5", dir, dir + "/bunny.obj");
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_EQ(piped.out.rfind("v ", 0) == 0 || piped.out.rfind('#', 0) == 0, true) << piped.out.substr(0, 80);
  EXPECT_NE(piped.out.find("\nf "), std::string::npos);
}

TEST_F(App, OneCommandLineGrammarEverywhere) {
  for (const char* cmd : {"--version", "simplify --version", "compare --version"}) {
    const AppRun r = run(cmd, dir);
    EXPECT_EQ(r.code, 0) << cmd;
    EXPECT_EQ(r.out.rfind("visimp ", 0), 0u) << r.out;
  }
  const std::string out = dir + "/o.ply";
  AppRun r = run("simplify " + bunny + " " + out + " --ratio 0", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--ratio must be in (0, 1]"), std::string::npos) << r.err;
  r = run("simplify " + bunny + " " + out + " --ratio 0.5 --target 100", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("not both"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out));
  // -o OUT wherever OUT is positional; both at once is a usage error.
  for (const std::string& cmd : {"simplify " + bunny + " -o " + out + " --ratio 0.5", "convert " + bunny + " -o " + out,
                                 "visibility " + bunny + " -o " + out + " --cameras 6 --resolution 64",
                                 "orient " + bunny + " -o " + out + " --cameras 6 --resolution 64"}) {
    std::filesystem::remove(out);
    EXPECT_EQ(run(cmd, dir).code, 0) << cmd;
    EXPECT_TRUE(std::filesystem::exists(out)) << cmd;
  }
  EXPECT_EQ(run("convert " + bunny + " " + out + " -o " + out, dir).code, 2);
  // An option a command would ignore is not offered (nor accepted).
  EXPECT_EQ(run("visibility-study --help", dir).out.find("--cameras"), std::string::npos);
  EXPECT_EQ(run("visibility-study " + bunny + " --cameras 18", dir).code, 2);
  // compare's levels always run one serial sequence: the flag that asks for it would do nothing.
  EXPECT_NE(run("simplify --help", dir).out.find("--serial-collapses"), std::string::npos);
  EXPECT_EQ(run("compare --help", dir).out.find("--serial-collapses"), std::string::npos);
}

TEST_F(App, AMissingGlContextIsABackendErrorNotACrash) {
  // Mesa's softpipe has no OpenGL 4.5: the osmesa backend must refuse up front, exit 1.
  ::setenv("GALLIUM_DRIVER", "softpipe", 1);
  const AppRun r = run("visibility " + bunny + " " + dir + "/v.ply --backend osmesa --cameras 6", dir);
  ::unsetenv("GALLIUM_DRIVER");
  EXPECT_EQ(r.code, 1) << r.err;
  EXPECT_NE(r.err.find("OpenGL 4.5"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/v.ply"));
}

TEST_F(App, OnlyTheOsmesaBackendLoadsMesa) {
  // libOSMesa (and Mesa's LLVM behind it) cost every process ~65 ms of relocations at start-up
  // when linked: it is opened at first use, by the osmesa backend only. glibc's loader lists
  // every object it maps under LD_DEBUG=files.
  ::setenv("LD_DEBUG", "files", 1);
  const AppRun info = run("info " + bunny, dir);
  const AppRun simplify = run("simplify " + bunny + " " + dir + "/s.ply --ratio 0.5", dir);
  const AppRun raster = run("visibility " + bunny + " " + dir + "/r.ply --cameras 6 --resolution 64", dir);
  const AppRun field = run("field build " + bunny + " -o " + dir + "/f.vfd --uv 4 --st 4", dir);
  const AppRun osmesa =
      run("visibility " + bunny + " " + dir + "/o.ply --backend osmesa --cameras 6 --resolution 64", dir);
  ::unsetenv("LD_DEBUG");
  for (const AppRun* r : {&info, &simplify, &raster, &field}) {
    EXPECT_EQ(r->code, 0);
    for (const char* library : {"libOSMesa", "libLLVM"}) {
      EXPECT_EQ(r->err.find(library), std::string::npos) << library << " in " << r->err.substr(0, 2000);
    }
  }
  EXPECT_EQ(osmesa.code, 0);
  EXPECT_NE(osmesa.err.find("libOSMesa"), std::string::npos) << osmesa.err.substr(0, 2000);  // the check can see it
}

TEST_F(App, NothingToSimplifyExitsOne) {
  const std::string empty = dir + "/vertices_only.ply";
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  write_mesh(m, empty);
  for (const std::string& cmd :
       {"simplify " + empty + " " + dir + "/o.ply --ratio 0.5", "visibility " + empty + " " + dir + "/o.ply",
        "compare " + empty + " -o " + dir + "/cmp"}) {
    const AppRun r = run(cmd, dir);
    EXPECT_EQ(r.code, 1) << cmd;
    EXPECT_NE(r.err.find(empty + ": no faces"), std::string::npos) << r.err;
  }
  EXPECT_EQ(run("info " + empty + " --json", dir).code, 0);  // describing it is fine
  EXPECT_EQ(run("convert " + empty + " " + dir + "/v.obj", dir).code, 0);
}

TEST_F(App, InfoReportsTopologyAsJson) {
  const AppRun r = run("info " + test::bundled_mesh("teapot.ply") + " --json", dir);
  ASSERT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("\"boundary_edges\": 160"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"components\": 3"), std::string::npos);
}

TEST_F(App, ConvertRoundTripsEveryFormat) {
  for (const char* ext : {"obj", "off", "stl", "ply"}) {
    const std::string out = dir + "/bunny." + ext;
    ASSERT_EQ(run("convert " + bunny + " " + out, dir).code, 0) << ext;
    EXPECT_EQ(read_mesh(out).num_faces(), 3674u) << ext;
  }
}

// Scene formats through assimp (Debian's assimp-testmodels): read everywhere a mesh is read,
// from a file or from stdin; refused as outputs (exit 2, nothing written); a scene assimp would
// read only in part is bad input (exit 1), one line naming the file.
TEST_F(App, ReadsSceneFormatsAndRefusesToWriteThem) {
  const std::string models = "/usr/share/assimp/models/";
  if (!std::filesystem::exists(models + "glTF2")) GTEST_SKIP() << "assimp-testmodels is not installed";
  const std::string glb = models + "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";
  AppRun r = run("info " + glb + " --json --no-visibility", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"faces\": 121496"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"input_format\": \"glb\""), std::string::npos) << r.out;
  r = run("convert - " + dir + "/duck.ply", dir, models + "Collada/duck.dae");  // stdin: the content decides
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_mesh(dir + "/duck.ply").num_faces(), 4212u);
  r = run("simplify " + models + "Collada/duck.dae " + dir + "/duck.obj --target 1000 --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(read_mesh(dir + "/duck.obj").num_faces(), 1000u);
  r = run("convert " + bunny + " " + dir + "/bunny.glb", dir);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("does not write"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/bunny.glb"));
  const std::string broken = models + "glTF2/IndexOutOfRange/IndexOutOfRange.gltf";
  r = run("convert " + broken + " " + dir + "/broken.ply", dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(broken), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/broken.ply"));
}

TEST_F(App, VisibilityWritesQualityJsonAndAPicture) {
  const AppRun r = run(
      "visibility " + bunny + " " + dir + "/v.ply --cameras 66 --resolution 200 --png " + dir + "/v.png --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"mesh_visibility\": 0.9"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"cameras\": 66"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"render\":"), std::string::npos) << r.out;
  const Mesh out = read_mesh(dir + "/v.ply");
  ASSERT_EQ(out.face_quality.size(), 3674u);
  ASSERT_EQ(out.vertex_quality.size(), out.num_vertices());
  EXPECT_EQ(test::slurp(dir + "/v.png").substr(1, 3), "PNG");
}

TEST_F(App, VisibilitySlicesMergeToTheSameFileBitForBit) {
  const std::string common = " --cameras 66 --resolution 160";
  ASSERT_EQ(run("visibility " + bunny + " " + dir + "/whole.ply" + common, dir).code, 0);
  ASSERT_EQ(run("visibility " + bunny + common + " --camera-range 0:30 --tally " + dir + "/a.bin", dir).code, 0);
  ASSERT_EQ(run("visibility " + bunny + common + " --camera-range 30:66 --tally " + dir + "/b.bin", dir).code, 0);
  // Missing cameras are an error, not a quietly different answer.
  AppRun partial = run("visibility-merge " + dir + "/a.bin -o " + dir + "/partial.ply --mesh " + bunny, dir);
  EXPECT_EQ(partial.code, 2);
  EXPECT_NE(partial.err.find("30..66"), std::string::npos) << partial.err;
  EXPECT_EQ(run("visibility-merge " + dir + "/a.bin " + dir + "/a.bin -o " + dir + "/x.bin", dir).code, 2);
  const AppRun merged =
      run("visibility-merge " + dir + "/b.bin " + dir + "/a.bin -o " + dir + "/merged.ply --mesh " + bunny, dir);
  ASSERT_EQ(merged.code, 0) << merged.err;
  EXPECT_EQ(test::slurp(dir + "/merged.ply"), test::slurp(dir + "/whole.ply"));
}

TEST_F(App, VisibilityRejectsBadCamerasAndOutputs) {
  { std::ofstream(dir + "/cams.txt") << "0 0 1\n1 nan 0\n"; }
  AppRun r = run("visibility " + bunny + " " + dir + "/v.ply --cameras " + dir + "/cams.txt", dir);
  EXPECT_EQ(r.code, 1);
  EXPECT_NE(r.err.find("cams.txt: line 2"), std::string::npos) << r.err;
  r = run("visibility " + bunny + " " + dir + "/v.obj", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("PLY"), std::string::npos) << r.err;
  r = run("visibility " + bunny + " " + dir + "/v.ply --backend vulkan", dir);
  EXPECT_EQ(r.code, 2);
  r = run("visibility " + bunny + " " + dir + "/v.ply --camera-range 5:3", dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir + "/v.ply"));
}

TEST_F(App, OrientRewindsAnInwardScanAndInfoSaysSo) {
  // The bunny wound inward, as it is commonly distributed.
  Mesh inward = read_mesh(bunny);
  for (Face& f : inward.faces) std::swap(f[1], f[2]);
  write_mesh(inward, dir + "/inward.ply");
  const AppRun before = run("info " + dir + "/inward.ply --json", dir);
  ASSERT_EQ(before.code, 0) << before.err;
  EXPECT_NE(before.out.find("\"seen_from_behind_faces\": 3674"), std::string::npos) << before.out;
  const AppRun r =
      run("orient " + dir + "/inward.ply " + dir + "/outward.ply --cameras 66 --resolution 200 --json", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"reversed_faces\": 3674"), std::string::npos) << r.out;
  const AppRun after = run("info " + dir + "/outward.ply --json", dir);
  EXPECT_NE(after.out.find("\"seen_from_behind_faces\": 0"), std::string::npos) << after.out;
  EXPECT_NE(run("info " + dir + "/outward.ply", dir).out.find("seen from behind      0 faces"), std::string::npos);
  // The V written by `visibility` does not care either.
  const AppRun v = run("visibility " + dir + "/inward.ply " + dir + "/v.ply --cameras 66 --resolution 200 --json", dir);
  EXPECT_NE(v.out.find("\"seen_from_behind_faces\": 3674"), std::string::npos) << v.out;
  EXPECT_EQ(run("orient " + dir + "/inward.ply " + dir + "/inward.ply", dir).code, 2);  // never over the input
  EXPECT_EQ(run("orient " + dir + "/missing.ply " + dir + "/o.ply", dir).code, 1);
}

TEST_F(App, VisibilityStudyReportsErrorAgainstTime) {
  const AppRun r = run(
      "visibility-study " + bunny + " --max-level 2 --resolution 128 --svg " + dir + "/s.svg --csv " + dir + "/s.csv",
      dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("level,cameras,seconds"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n2,66,"), std::string::npos) << r.out;
  EXPECT_EQ(test::slurp(dir + "/s.csv"), r.out);
  EXPECT_NE(test::slurp(dir + "/s.svg").find("<svg"), std::string::npos);
}

TEST_F(App, MetroAndImageErrorReportAPair) {
  ASSERT_EQ(run("simplify " + bunny + " " + dir + "/small.ply --ratio 0.1", dir).code, 0);
  AppRun r = run("metro " + bunny + " " + dir + "/small.ply --json --error-ply " + dir + "/err.ply", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"hausdorff_relative\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"histogram_area_share\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"diagonal_of\": \"A\""), std::string::npos) << r.out;
  const Mesh map = read_mesh(dir + "/err.ply");
  EXPECT_EQ(map.vertex_quality.size(), map.num_vertices());
  r = run("metro " + bunny + " " + dir + "/small.ply", dir);
  EXPECT_NE(r.out.find("Hausdorff distance:"), std::string::npos) << r.out;
  r = run("imgerr " + bunny + " " + bunny + " --json --resolution 64", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"rms\": 0,"), std::string::npos) << r.out;
  r = run("imgerr " + bunny + " " + dir + "/small.ply --resolution 64 --diff-prefix " + dir + "/diff", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir + "/diff19.png"));
  // V-weighted needs V on A.
  EXPECT_EQ(run("metro " + bunny + " " + dir + "/small.ply --visible", dir).code, 1);
}

// Several B against one A: A's views drawn once, each B's numbers those of a call of its own,
// a JSON array of the one-B summaries; a bad B fails the call with nothing on stdout.
TEST_F(App, ImageErrorMeasuresSeveralResultsAgainstOneInput) {
  ASSERT_EQ(run("simplify " + bunny + " " + dir + "/a.ply --ratio 0.3", dir).code, 0);
  ASSERT_EQ(run("simplify " + bunny + " " + dir + "/b.ply --ratio 0.05", dir).code, 0);
  auto rms_field = [](const std::string& json, std::size_t from = 0) {
    const std::size_t at = json.find("\"rms\": ", from);
    return at == std::string::npos ? std::string() : json.substr(at, json.find(',', at) - at);
  };
  const AppRun one_a = run("imgerr " + bunny + " " + dir + "/a.ply --json --resolution 64", dir);
  const AppRun one_b = run("imgerr " + bunny + " " + dir + "/b.ply --json --resolution 64", dir);
  const AppRun both = run("imgerr " + bunny + " " + dir + "/a.ply " + dir + "/b.ply --json --resolution 64", dir);
  ASSERT_EQ(both.code, 0) << both.err;
  ASSERT_FALSE(rms_field(one_a.out).empty()) << one_a.out;
  EXPECT_EQ(both.out.find('['), both.out.find_first_not_of(" \n")) << both.out;  // an array
  const std::size_t second = both.out.find("\"command\"", both.out.find("\"command\"") + 1);
  ASSERT_NE(second, std::string::npos) << both.out;
  EXPECT_EQ(rms_field(both.out), rms_field(one_a.out));
  EXPECT_EQ(rms_field(both.out, second), rms_field(one_b.out));
  EXPECT_NE(rms_field(one_a.out), rms_field(one_b.out));
  const AppRun bad = run("imgerr " + bunny + " " + dir + "/a.ply " + dir + "/missing.ply --json", dir);
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(bad.out.empty()) << bad.out;
  EXPECT_NE(bad.err.find("missing.ply"), std::string::npos) << bad.err;
  // Difference images: P<k>_<view>.png per B, each the one-B call's P<view>.png; a B that
  // cannot be read fails the call before any image is written.
  ASSERT_EQ(run("imgerr " + bunny + " " + dir + "/b.ply --resolution 64 --diff-prefix " + dir + "/one", dir).code, 0);
  ASSERT_EQ(run("imgerr " + bunny + " " + dir + "/a.ply " + dir + "/b.ply --resolution 64 --diff-prefix " + dir +
                    "/many",
                dir)
                .code,
            0);
  for (int view : {0, 7, 19}) {
    const std::string one = test::slurp(dir + "/one" + std::to_string(view) + ".png");
    const std::string first = test::slurp(dir + "/many1_" + std::to_string(view) + ".png");
    ASSERT_FALSE(one.empty());
    ASSERT_FALSE(first.empty());
    EXPECT_EQ(test::slurp(dir + "/many2_" + std::to_string(view) + ".png"), one) << view;
    EXPECT_NE(first, one) << view;
  }
  EXPECT_EQ(run("imgerr " + bunny + " " + dir + "/a.ply " + dir + "/missing.ply --diff-prefix " + dir + "/none",
                dir)
                .code,
            1);
  EXPECT_FALSE(std::filesystem::exists(dir + "/none1_0.png"));
}

// Several B against one A: A's samples and tree made once, each B's numbers and error map
// those of a call of its own (FILE_<k>.ext per B); a bad B, or an error map that would replace
// an input, fails the call before anything is written or printed.
TEST_F(App, MetroMeasuresSeveralResultsAgainstOneInput) {
  ASSERT_EQ(run("simplify " + bunny + " " + dir + "/a.ply --ratio 0.3", dir).code, 0);
  ASSERT_EQ(run("simplify " + bunny + " " + dir + "/b.ply --ratio 0.05", dir).code, 0);
  auto field = [](const std::string& json, const std::string& name, std::size_t from = 0) {
    const std::size_t at = json.find("\"" + name + "\": ", from);
    return at == std::string::npos ? std::string() : json.substr(at, json.find(',', at) - at);
  };
  const std::string common = " --json --samples 20000";
  const AppRun one_a = run("metro " + bunny + " " + dir + "/a.ply --error-ply " + dir + "/ea.ply" + common, dir);
  const AppRun one_b = run("metro " + bunny + " " + dir + "/b.ply --error-ply " + dir + "/eb.ply" + common, dir);
  const AppRun both =
      run("metro " + bunny + " " + dir + "/a.ply " + dir + "/b.ply --error-ply " + dir + "/e.ply" + common, dir);
  ASSERT_EQ(one_a.code, 0) << one_a.err;
  ASSERT_EQ(one_b.code, 0) << one_b.err;
  ASSERT_EQ(both.code, 0) << both.err;
  ASSERT_FALSE(field(one_a.out, "hausdorff").empty()) << one_a.out;
  EXPECT_EQ(both.out.find('['), both.out.find_first_not_of(" \n")) << both.out;  // an array
  const std::size_t second = both.out.find("\"command\"", both.out.find("\"command\"") + 1);
  ASSERT_NE(second, std::string::npos) << both.out;
  for (const char* name : {"hausdorff", "rms", "mean"}) {
    EXPECT_EQ(field(both.out, name), field(one_a.out, name)) << name;
    EXPECT_EQ(field(both.out, name, second), field(one_b.out, name)) << name;
  }
  EXPECT_NE(field(one_a.out, "hausdorff"), field(one_b.out, "hausdorff"));
  ASSERT_FALSE(test::slurp(dir + "/ea.ply").empty());
  ASSERT_FALSE(test::slurp(dir + "/eb.ply").empty());
  EXPECT_EQ(test::slurp(dir + "/e_1.ply"), test::slurp(dir + "/ea.ply"));
  EXPECT_EQ(test::slurp(dir + "/e_2.ply"), test::slurp(dir + "/eb.ply"));
  EXPECT_EQ(both.out.back(), '\n');  // the array ends its line, as one summary does
  const AppRun text = run("metro " + bunny + " " + dir + "/a.ply " + dir + "/b.ply --samples 20000", dir);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("b.ply ("), std::string::npos) << text.out;

  const AppRun bad =
      run("metro " + bunny + " " + dir + "/a.ply " + dir + "/missing.ply --json --error-ply " + dir + "/x.ply", dir);
  EXPECT_EQ(bad.code, 1);
  EXPECT_TRUE(bad.out.empty()) << bad.out;
  EXPECT_NE(bad.err.find("missing.ply"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x_1.ply"));
  // The error map of one B named as that B: refused, B unchanged.
  const std::string b_before = test::slurp(dir + "/b.ply");
  const AppRun clobber = run("metro " + bunny + " " + dir + "/b.ply --error-ply " + dir + "/b.ply", dir);
  EXPECT_EQ(clobber.code, 2) << clobber.err;
  EXPECT_NE(clobber.err.find("overwrite"), std::string::npos) << clobber.err;
  EXPECT_EQ(test::slurp(dir + "/b.ply"), b_before);
  EXPECT_EQ(run("metro " + bunny + " " + dir + "/a.ply " + dir + "/b.ply --error-ply -", dir).code, 2);
  // A numbered error map named as some B (e_2.ply for the second B, here the first B itself).
  ASSERT_EQ(run("simplify " + bunny + " " + dir + "/e_2.ply --ratio 0.3", dir).code, 0);
  const std::string e2_before = test::slurp(dir + "/e_2.ply");
  EXPECT_EQ(run("metro " + bunny + " " + dir + "/e_2.ply " + dir + "/b.ply --error-ply " + dir + "/e.ply", dir).code,
            2);
  EXPECT_EQ(test::slurp(dir + "/e_2.ply"), e2_before);
  EXPECT_EQ(run("metro " + bunny + " - -", dir).code, 2);  // standard input read once
  // A B whose only face has no area fails, named, before the first B's error map is written.
  Mesh flat;
  flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  flat.faces = {{0, 1, 2}};
  write_mesh(flat, dir + "/flat.ply");
  const AppRun degenerate =
      run("metro " + bunny + " " + dir + "/a.ply " + dir + "/flat.ply --error-ply " + dir + "/d.ply", dir);
  EXPECT_EQ(degenerate.code, 1);
  EXPECT_NE(degenerate.err.find("flat.ply: no face with area"), std::string::npos) << degenerate.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/d_1.ply"));
  const AppRun alone = run("metro " + bunny, dir);
  EXPECT_EQ(alone.code, 2);
  EXPECT_NE(alone.err.find("expected at least 2 file argument(s), got 1"), std::string::npos) << alone.err;
}

TEST_F(App, SimplifyVgWritesEveryLevelAndDropsHiddenFaces) {
  const std::string esp = test::bundled_mesh("kicad_esp_wroom02.ply");
  const AppRun r = run("simplify " + esp + " " + dir +
                           "/esp.ply --method vg --drop-hidden --levels 3 --cameras 66 "
                           "--resolution 256 --json",
                       dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"method\": \"vg\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"faces_removed\""), std::string::npos) << r.out;
  // Three snapshots named by their face counts, each a valid mesh of that count.
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("esp_", 0) != 0) continue;
    ++files;
    const std::size_t faces = std::stoul(name.substr(4, name.size() - 8));
    EXPECT_EQ(read_mesh(entry.path().string()).num_faces(), faces) << name;
  }
  EXPECT_EQ(files, 3u);
  // VG without V anywhere is refused before any work.
  const AppRun bad =
      run("simplify " + bunny + " " + dir + "/b.ply --ratio 0.5 --method vg --weights-from-quality", dir);
  EXPECT_EQ(bad.code, 1) << bad.err;
  EXPECT_NE(bad.err.find("bunny.ply"), std::string::npos) << bad.err;
  EXPECT_EQ(run("simplify " + bunny + " - --levels 3 --format ply", dir).code, 2);
}

TEST_F(App, CompareWritesTheReportAndTheTableRow) {
  const AppRun r = run("compare " + bunny + " -o " + dir +
                           "/cmp --targets 1000,300 --cameras 18 --resolution 128 "
                           "--metro-samples 100000 --image-resolution 64 --json",
                       dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"less_image_error_with_vg_percent\""), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"unreached_levels\": \"\""), std::string::npos) << r.out;  // the bunny reaches both
  EXPECT_EQ(r.err.find("note:"), std::string::npos) << r.err;
  // The options it ran with, as simplify --json lists them (JsonSummariesRecordEveryOptionTheyRanWith).
  const std::string options = r.out.substr(r.out.find("\"options\": {"));
  for (const char* field : {"\"targets\": \"1000,300\"", "\"cameras\": \"18\"", "\"resolution\": 128",
                            "\"image_resolution\": 64", "\"metro_samples\": 100000", "\"tie_noise\": 0",
                            "\"quadric_weights\": \"area\"", "\"max_normal_change\": 80"})
    EXPECT_NE(options.substr(0, options.find('}')).find(field), std::string::npos) << field << "\n" << r.out;
  std::ifstream results_json(dir + "/cmp/results.json");  // and so does the report it leaves behind
  const std::string results((std::istreambuf_iterator<char>(results_json)), std::istreambuf_iterator<char>());
  EXPECT_NE(results.find("\"targets\": \"1000,300\""), std::string::npos) << results;
  EXPECT_NE(results.find("\"image_resolution\": 64"), std::string::npos) << results;
  for (const char* f : {"report.html", "results.csv", "results.json", "image_error_vs_seconds.svg", "visibility.png",
                        "side_by_side.png"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/cmp/" + f)) << f;
  const AppRun text = run("compare " + bunny + " -o " + dir +
                              "/cmp2 --targets 500 --cameras 6 --resolution 64 "
                              "--metro-samples 10000 --image-resolution 32 --tie-noise 1",
                          dir);
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("| bunny | 3674 |"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("near-tie run(s), per level: above their spread at "), std::string::npos) << text.out;
  EXPECT_EQ(run("compare " + bunny + " --targets 9999", dir).code, 2);
  const AppRun no_quality = run("compare " + bunny + " --weights-from-quality -o " + dir + "/cmp3", dir);
  EXPECT_EQ(no_quality.code, 1);
  EXPECT_NE(no_quality.err.find("bunny.ply: "), std::string::npos) << no_quality.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/cmp3"));
}

TEST_F(App, PatchesBuildQueryAndStudy) {
  const std::string vbf = dir + "/bunny.vbf";
  const AppRun build =
      run("patches build " + bunny + " -o " + vbf +
              " --patches 120 --cameras 66 --resolution 160 "
              "--patch-ply " +
              dir + "/patches.ply --patch-png " + dir + "/patches.png --visibility " + dir + "/v.ply --json",
          dir);
  ASSERT_EQ(build.code, 0) << build.err;
  EXPECT_NE(build.out.find("\"units\": 120"), std::string::npos) << build.out;
  EXPECT_NE(build.out.find("\"mesh_visibility\""), std::string::npos) << build.out;
  EXPECT_EQ(read_mesh(dir + "/patches.ply").face_quality.size(), 3674u);
  EXPECT_EQ(read_mesh(dir + "/v.ply").face_quality.size(), 3674u);
  EXPECT_TRUE(std::filesystem::exists(dir + "/patches.png"));

  // One patch number per line, then the culled mesh: exactly the faces of those patches.
  const AppRun listed = run("patches query " + vbf + " --direction 0,0,1", dir);
  ASSERT_EQ(listed.code, 0) << listed.err;
  std::set<int> patches;
  std::istringstream lines(listed.out);
  for (int p; lines >> p;) patches.insert(p);
  EXPECT_GT(patches.size(), 20u);
  EXPECT_LT(patches.size(), 120u);
  const AppRun culled =
      run("patches query " + vbf + " --direction 0,0,1 --mesh " + bunny + " -o " + dir + "/c.ply", dir);
  ASSERT_EQ(culled.code, 0) << culled.err;
  const Mesh tagged = read_mesh(dir + "/patches.ply");
  std::size_t expected = 0;
  for (float q : tagged.face_quality) expected += patches.count(static_cast<int>(q));
  EXPECT_EQ(read_mesh(dir + "/c.ply").num_faces(), expected);

  // The wrong mesh, a missing view and a damaged file are refused.
  const AppRun wrong =
      run("patches query " + vbf + " --direction 0,0,1 --mesh " + dir + "/c.ply -o " + dir + "/x.ply", dir);
  EXPECT_EQ(wrong.code, 1);
  EXPECT_NE(wrong.err.find("belongs to another mesh"), std::string::npos) << wrong.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.ply"));
  EXPECT_EQ(run("patches query " + vbf, dir).code, 2);
  EXPECT_EQ(run("patches query " + bunny + " --direction 1,0,0", dir).code, 1);
  EXPECT_EQ(run("patches build " + bunny + " -o " + bunny, dir).code, 2);

  const AppRun study = run("patches study " + bunny + " -o " + dir +
                               "/study --patch-counts 30,300 --max-cameras 66 "
                               "--viewpoints 50 --pixel-views 3 --resolution 96 --timing-backend none",
                           dir);
  ASSERT_EQ(study.code, 0) << study.err;
  EXPECT_NE(study.out.find("300 patches"), std::string::npos) << study.out;
  for (const char* f : {"study.csv", "study.json", "culling_vs_samples.svg", "culling_vs_patches.svg"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/study/" + f)) << f;
  // 3 units × 3 camera levels (6, 18, 66) + 3 pixel rows + the header.
  std::istringstream csv(test::slurp(dir + "/study/study.csv"));
  std::size_t rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 1u + 3u * 3u + 3u);
}

// The PLY `source_face` column of a binary PLY written by visimp (float xyz, no quality).
std::vector<std::uint32_t> source_faces(const std::string& path) {
  const std::string bytes = test::slurp(path);
  const std::size_t body = bytes.find("end_header\n") + 11;
  EXPECT_NE(bytes.find("property uint source_face"), std::string::npos);
  const std::size_t vertices = std::stoul(bytes.substr(bytes.find("element vertex ") + 15));
  const std::size_t faces = std::stoul(bytes.substr(bytes.find("element face ") + 13));
  std::vector<std::uint32_t> out(faces);
  std::size_t at = body + vertices * 12;
  for (std::size_t f = 0; f < faces; ++f, at += 17) std::memcpy(&out[f], bytes.data() + at + 13, 4);
  return out;
}

std::size_t json_count(const std::string& json, const std::string& key) {
  const std::size_t at = json.find("\"" + key + "\": ");
  return at == std::string::npos ? 0 : std::stoul(json.substr(at + key.size() + 4));
}

TEST_F(App, FieldBuildQueryAndCulledMesh) {
  const std::string vfd = dir + "/bunny.vfd";
  const AppRun built = run("field build " + bunny + " -o " + vfd + " --uv 8 --st 8 --ids 3 --json", dir);
  ASSERT_EQ(built.code, 0) << built.err;
  EXPECT_NE(built.out.find("\"compression_ratio\""), std::string::npos);
  const std::string view = " --view 12,14,18 --subsample 4 --interp uvst";
  const AppRun listed = run("field query " + vfd + view, dir);
  ASSERT_EQ(listed.code, 0) << listed.err;
  std::set<int> cells;
  std::istringstream lines(listed.out);
  for (int c; lines >> c;) cells.insert(c);
  const AppRun summary = run("field query " + vfd + view + " --json", dir);
  ASSERT_EQ(summary.code, 0) << summary.err;
  EXPECT_EQ(json_count(summary.out, "cells_marked"), cells.size());
  EXPECT_GT(cells.size(), 0u);
  EXPECT_LT(json_count(summary.out, "cells_marked"), json_count(summary.out, "cells_total"));
  EXPECT_EQ(json_count(summary.out, "faces_total"), 3674u);

  const AppRun culled = run("field query " + vfd + view + " --json --mesh " + bunny + " -o " + dir + "/c.ply", dir);
  ASSERT_EQ(culled.code, 0) << culled.err;
  const Mesh input = read_mesh(bunny), kept = read_mesh(dir + "/c.ply");
  const std::vector<std::uint32_t> source = source_faces(dir + "/c.ply");
  ASSERT_EQ(kept.num_faces(), json_count(culled.out, "faces_kept"));
  ASSERT_EQ(source.size(), kept.num_faces());
  EXPECT_TRUE(std::is_sorted(source.begin(), source.end()));
  for (std::size_t f = 0; f < source.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = kept.positions[kept.faces[f][k]], b = input.positions[input.faces[source[f]][k]];
      ASSERT_NEAR(a.x, b.x, 1e-6);
      ASSERT_NEAR(a.z, b.z, 1e-6);
    }
  }
  // The field refuses another mesh.
  const AppRun wrong = run("field query " + vfd + view + " --mesh " + dir + "/c.ply -o " + dir + "/x.ply", dir);
  EXPECT_EQ(wrong.code, 1);
  EXPECT_NE(wrong.err.find("another mesh"), std::string::npos) << wrong.err;
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.ply"));
}

TEST_F(App, FieldBadInputExitsTwoNamingTheFlag) {
  const std::string vfd = dir + "/bunny.vfd";
  ASSERT_EQ(run("field build " + bunny + " -o " + vfd + " --uv 4 --st 4", dir).code, 0);
  for (const auto& [args, flag] : std::vector<std::pair<std::string, std::string>>{
           {"field query " + vfd, "--view"},
           {"field query " + vfd + " --view 1,2", "--view"},
           {"field query " + vfd + " --view 1,2,nan", "--view"},
           {"field query " + vfd + " --view a,b,c", "--view"},
           {"field query " + vfd + " --view 9,9,9 --look 9,9,9", "--look"},
           {"field query " + vfd + " --view 0,4,0", "--view"},  // inside the bunny
           {"field query " + vfd + " --view 9,9,9 --subsample 3", "--subsample"},
           {"field query " + vfd + " --view 9,9,9 --interp cubic", "interpolation"},
           {"field query " + vfd + " --view 9,9,9 --fov 0", "--fov"},
           {"field query " + vfd + " --view 9,9,9 --resolution 8", "--resolution"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --grid 0", "--grid"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --grid 256", "--grid"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --uv 1", "--uv"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --st 65", "--st"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --ids 9", "--ids"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --ids 0", "--ids"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --slabs 2", "--slabs"},
           {"field build " + bunny + " -o " + dir + "/x.vfd --cells octree", "cell mode"},
       }) {
    const AppRun r = run(args, dir);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/x.vfd"));
  // A damaged field file: exit 1, naming the file.
  std::ofstream(dir + "/cut.vfd", std::ios::binary) << test::slurp(vfd).substr(0, 100);
  const AppRun cut = run("field query " + dir + "/cut.vfd --view 9,9,9", dir);
  EXPECT_EQ(cut.code, 1);
  EXPECT_NE(cut.err.find("cut.vfd"), std::string::npos) << cut.err;
}

TEST_F(App, SceneParkWritesAScene) {
  const AppRun park = run("scene park -o " + dir + "/park.json --objects 12 --area 80,50 --seed 3 --meshes " + bunny +
                              "," + test::bundled_mesh("kicad_esp_wroom02.ply") + ":z --json",
                          dir);
  ASSERT_EQ(park.code, 0) << park.err;
  EXPECT_EQ(json_count(park.out, "objects"), 12u);
  const AppRun info = run("scene info " + dir + "/park.json --json", dir);
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_EQ(json_count(info.out, "objects"), 12u);
  EXPECT_EQ(json_count(info.out, "faces"), json_count(park.out, "faces"));
  for (const char* bad : {"scene park --objects 3", "scene park -o x.json --area 5",
                                 "scene park -o x.json --objects 0", "scene frobnicate"}) {
    const AppRun r = run(bad, dir);
    EXPECT_EQ(r.code, 2) << bad << ": " << r.err;
  }
  std::ofstream(dir + "/broken.json") << "{\"format\": \"visimp-scene\", \"version\": 1, \"objects\": [{}]}";
  const AppRun broken = run("scene info " + dir + "/broken.json", dir);
  EXPECT_EQ(broken.code, 1);
  EXPECT_NE(broken.err.find("broken.json"), std::string::npos) << broken.err;
}

TEST_F(App, CellsBuildAndWalkAPark) {
  const std::string scene = dir + "/park.json", cells = dir + "/cells", walked = dir + "/walk";
  ASSERT_EQ(run("scene park -o " + scene + " --objects 6 --area 60,60 --object-size 8 --seed 2 --meshes " + bunny +
                    "," + test::bundled_mesh("teapot.ply"),
                dir)
                .code,
            0);
  const AppRun built = run("cells build " + scene + " -o " + cells +
                               " --cell-size 10 --eye-height 3 --resolution 128 --max-capture 128 --path auto "
                               "--frames 12 --json",
                           dir);
  ASSERT_EQ(built.code, 0) << built.err;
  EXPECT_GT(json_count(built.out, "cells"), 6u);
  EXPECT_GT(json_count(built.out, "svmesh") + json_count(built.out, "mvmesh"), 0u);
  EXPECT_TRUE(std::filesystem::exists(cells + "/cells.json"));
  const AppRun walk = run("cells walk " + scene + " " + cells + " --path auto --frames 12 -o " + walked + " --json", dir);
  ASSERT_EQ(walk.code, 0) << walk.err;
  EXPECT_EQ(json_count(walk.out, "frames"), 12u);
  EXPECT_NE(walk.out.find("\"psnr\""), std::string::npos);
  const std::string csv = test::slurp(walked + "/frames.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 13);  // a header and 12 frames
  EXPECT_TRUE(std::filesystem::exists(walked + "/walk.json"));
  // Bad usage names the flag; a path leaving the built cells, or another scene, is refused.
  for (const auto& [args, flag] : std::vector<std::pair<std::string, std::string>>{
           {"cells build " + scene, "-o"},
           {"cells build " + scene + " -o " + dir + "/c2 --tl 0", "--tl"},
           {"cells build " + scene + " -o " + dir + "/c2 --cell-size -1", "size"},
           {"cells walk " + scene + " " + cells, "--path"},
           {"cells walk " + scene + " " + cells + " --path auto --prefetch maybe", "--prefetch"},
           {"cells frobnicate", "frobnicate"}}) {
    const AppRun r = run(args, dir);
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(flag), std::string::npos) << args << ": " << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(dir + "/c2"));
  std::ofstream(dir + "/away.txt") << "5000 5000 3 1 0 0\n";
  const AppRun away = run("cells walk " + scene + " " + cells + " --path " + dir + "/away.txt", dir);
  EXPECT_EQ(away.code, 1);
  EXPECT_NE(away.err.find("not built"), std::string::npos) << away.err;
  ASSERT_EQ(run("scene park -o " + dir + "/other.json --objects 6 --area 60,60 --object-size 8 --seed 3 --meshes " +
                    bunny,
                dir)
                .code,
            0);
  const AppRun other = run("cells walk " + dir + "/other.json " + cells + " --path auto", dir);
  EXPECT_EQ(other.code, 1);
  EXPECT_NE(other.err.find("another scene"), std::string::npos) << other.err;
}

}  // namespace
}  // namespace visimp
