// Every reader on broken input: a typed IoError naming the file and the problem, never a
// crash or an unbounded allocation.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "input_catalogue.h"
#include "test_meshes.h"
#include "visimp/core/errors.h"
#include "visimp/io/mesh_io.h"

namespace visimp {
namespace {

TEST(MalformedInput, CatalogueHasFortyCases) { EXPECT_GE(test::bad_inputs().size(), 40u); }

TEST(MalformedInput, EveryCaseThrowsIoErrorNamingTheFileAndProblem) {
  for (const test::BadInput& c : test::bad_inputs()) {
    SCOPED_TRACE(c.name);
    try {
      read_mesh_from_bytes(c.bytes, format_from_path(c.file), "bad-file.x");
      ADD_FAILURE() << "no exception for " << c.name;
    } catch (const IoError& e) {
      EXPECT_EQ(e.file(), "bad-file.x");
      EXPECT_NE(std::string(e.what()).find(c.expected), std::string::npos) << e.what();
    }
  }
}

TEST(MalformedInput, MissingFileAndDirectoryNameThePath) {
  const std::string dir = test::temp_dir("malformed");
  try {
    read_mesh(dir + "/missing.ply");
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.ply"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos);
  }
  EXPECT_THROW(read_mesh(dir + "/"), UsageError);  // no extension to go by
  try {
    read_mesh(dir, Format::ply);
    ADD_FAILURE();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("directory"), std::string::npos);
  }
}

}  // namespace
}  // namespace visimp
