// Issue 6 end to end: the whole bad-input catalogue through the apps, extreme-but-valid
// meshes through every stage, determinism across thread counts, and no data loss when a
// write is killed.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "app_runner.h"
#include "input_catalogue.h"
#include "test_meshes.h"
#include "visimp/core/validate.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

using test::AppRun;
using test::run;
using test::slurp;

class Hardening : public ::testing::Test {
 protected:
  void SetUp() override { dir = test::temp_dir(::testing::UnitTest::GetInstance()->current_test_info()->name()); }
  std::string dir;
};

TEST_F(Hardening, EveryBadInputFailsWithOneLineNamingTheFileAndNoOutput) {
  const auto inputs = test::bad_inputs();
  ASSERT_GE(inputs.size(), 40u);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const test::BadInput& c = inputs[i];
    SCOPED_TRACE(c.name);
    const std::string in = dir + "/case" + std::to_string(i) + "_" + c.file;
    std::ofstream(in, std::ios::binary) << c.bytes;
    for (const std::string command : {"simplify", "visibility"}) {
      const std::string out = dir + "/out.ply";
      const AppRun r = run(command + " " + in + " " + out + (command == "simplify" ? " --ratio 0.5" : ""), dir);
      EXPECT_EQ(r.code, 1) << command << ": " << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      EXPECT_NE(r.err.find(in), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
      EXPECT_FALSE(std::filesystem::exists(out));
    }
  }
}

bool all_finite(const Mesh& m) {
  for (const Vec3& p : m.positions)
    if (!is_finite(p)) return false;
  for (float q : m.face_quality)
    if (!std::isfinite(q) || q < 0 || q > 1) return false;
  return true;
}

TEST_F(Hardening, ExtremeMeshesGetThroughEveryStage) {
  for (const test::ExtremeMesh& e : test::extreme_meshes()) {
    SCOPED_TRACE(e.name);
    const std::string in = dir + "/in.ply";
    WriteOptions binary_double;
    binary_double.force_double = true;
    write_mesh(e.mesh, in, std::nullopt, binary_double);
    AppRun r = run("simplify " + in + " " + dir + "/simple.ply --ratio 0.3", dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const Mesh simple = read_mesh(dir + "/simple.ply");
    EXPECT_TRUE(validate(simple).ok());
    EXPECT_TRUE(all_finite(simple));
    EXPECT_LT(simple.num_faces(), e.mesh.num_faces());
    r = run("visibility " + in + " " + dir + "/v.ply --cameras 18 --resolution 96", dir);
    ASSERT_EQ(r.code, 0) << r.err;
    const Mesh v = read_mesh(dir + "/v.ply");
    EXPECT_EQ(v.face_quality.size(), e.mesh.num_faces());
    EXPECT_TRUE(all_finite(v));
  }
}

// JSON with the timings removed: everything else must not depend on the thread count.
std::string without_seconds(const std::string& json) {
  std::string out;
  bool in_seconds = false;
  std::istringstream lines(json);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("\"seconds\"") != std::string::npos) in_seconds = line.find('{') != std::string::npos;
    else if (in_seconds) in_seconds = line.find('}') == std::string::npos;
    else out += line + "\n";
  }
  return out;
}

TEST_F(Hardening, SameBytesAndNumbersForOneAndTwoThreads) {
  const std::string mesh = test::bundled_mesh("kicad_esp_wroom02.ply");
  const AppRun one = run("visibility " + mesh + " " + dir + "/one.ply --cameras 66 --resolution 200 --threads 1 --json", dir);
  const AppRun two = run("visibility " + mesh + " " + dir + "/two.ply --cameras 66 --resolution 200 --threads 2 --json", dir);
  ASSERT_EQ(one.code, 0) << one.err;
  ASSERT_EQ(two.code, 0) << two.err;
  EXPECT_EQ(slurp(dir + "/one.ply"), slurp(dir + "/two.ply"));
  std::string a = without_seconds(one.out), b = without_seconds(two.out);
  a.replace(a.find("one.ply"), 7, "x");
  b.replace(b.find("two.ply"), 7, "x");
  EXPECT_EQ(a, b);
  EXPECT_NE(a.find("mesh_visibility"), std::string::npos);
}

TEST_F(Hardening, KilledWriteLeavesTheOldFile) {
  // A 2M-face grid written as ASCII PLY takes long enough to be killed mid-write.
  const std::string in = dir + "/big.ply", out = dir + "/out.ply";
  write_mesh(test::grid(1000), in);
  const std::string old_content = "the previous output\n";
  for (int delay_ms : {50, 150, 300, 600}) {
    std::ofstream(out, std::ios::binary | std::ios::trunc) << old_content;
    const pid_t pid = fork();
    if (pid == 0) {
      execl(VISIMP_APP, VISIMP_APP, "convert", in.c_str(), out.c_str(), "--ascii", static_cast<char*>(nullptr));
      _exit(127);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    const std::string now = slurp(out);
    // Either the old file, untouched, or (if the convert finished first) the whole new one.
    if (now != old_content) {
      ASSERT_TRUE(WIFEXITED(status)) << "killed, yet " << out << " changed";
      EXPECT_EQ(read_mesh(out).num_faces(), 2000000u);
    }
  }
}

}  // namespace
}  // namespace visimp
