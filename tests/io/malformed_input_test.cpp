// Every reader on broken input: a typed IoError naming the file and the problem, never a
// crash or an unbounded allocation.
#include <gtest/gtest.h>

#include <fstream>

#include <cstring>
#include <string>

#include "input_catalogue.h"
#include "temp_dir.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

TEST(MalformedInput, CatalogueHasSixtyCases) { EXPECT_GE(test::bad_inputs().size(), 60u); }

// Through read_mesh(path), as the apps read: the format from the extension or, where that is
// missing, unknown or wrong, from the content.
TEST(MalformedInput, EveryCaseThrowsIoErrorNamingTheFileAndProblem) {
  const test::TempDir temp("catalogue");
  for (const test::BadInput& c : test::bad_inputs()) {
    SCOPED_TRACE(c.name);
    const std::string path = temp.path() + "/" + c.file;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << c.bytes;
    if (c.readable) {
      EXPECT_EQ(read_mesh(path).num_faces(), 0u);  // refused by the commands, not the readers
      continue;
    }
    try {
      read_mesh(path);
      ADD_FAILURE() << "no exception for " << c.name;
    } catch (const IoError& e) {
      EXPECT_EQ(e.file().substr(0, path.size()), path);
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
}

TEST(MalformedInput, MissingFileAndDirectoryNameThePath) {
  const test::TempDir temp("malformed");
  const std::string& dir = temp.path();
  try {
    read_mesh(dir + "/missing.ply");
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.ply"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos);
  }
  EXPECT_THROW(read_mesh(dir + "/"), IoError);  // a directory, whatever its name says
  try {
    read_mesh(dir, Format::ply);
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("directory"), std::string::npos);
  }
}

}  // namespace
}  // namespace visimp
