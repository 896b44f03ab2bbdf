// The CLI's promise: every failure is one line on stderr naming the file, a non-zero exit,
// no crash and nothing on stdout.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "test_util.h"

namespace pb4u {
namespace {

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

void expect_clean_failure(const std::string& path, const std::string& reason) {
  test::CommandResult r = test::run_pb4u("-q inspect '" + path + "'");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_EQ(r.err.rfind("pb4u: error: " + path + ": ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

class BadMeshFiles : public ::testing::Test {
 protected:
  std::string dir = test::temp_dir("badmesh");
  std::string file(const std::string& name, const std::string& text) {
    std::string p = dir + "/" + name;
    test::write_file(p, text);
    return p;
  }
};

TEST_F(BadMeshFiles, Missing) { expect_clean_failure(dir + "/nope.obj", "no such file"); }

TEST_F(BadMeshFiles, Empty) { expect_clean_failure(file("empty.obj", ""), "empty"); }

TEST_F(BadMeshFiles, Directory) { expect_clean_failure(dir, "directory"); }

TEST_F(BadMeshFiles, NanCoordinates) {
  expect_clean_failure(file("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), "non-finite");
}

TEST_F(BadMeshFiles, OutOfRangeIndexObj) {
  expect_clean_failure(file("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"), "out of range");
}

TEST_F(BadMeshFiles, OutOfRangeIndexPly) {
  expect_clean_failure(
      file("oor.ply",
           "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
           "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"),
      "out of range");
}

TEST_F(BadMeshFiles, NoTriangles) {
  expect_clean_failure(file("points.obj", "v 0 0 0\nv 1 0 0\n"), "cannot read mesh");
}

TEST_F(BadMeshFiles, AllDegenerate) {
  expect_clean_failure(file("line.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), "degenerate");
}

TEST_F(BadMeshFiles, RandomBytes) {
  std::mt19937 rng(7);
  for (const char* ext : {".obj", ".ply", ".stl", ".glb", ".bin"}) {
    std::string bytes(4096, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    expect_clean_failure(file(std::string("random") + ext, bytes), "cannot read mesh");
  }
}

TEST(Cli, HelpVersionAndUnknownCommand) {
  test::CommandResult r = test::run_pb4u("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("inspect"), std::string::npos);
  r = test::run_pb4u("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("pb4u " PB4U_VERSION), std::string::npos) << r.out;
  r = test::run_pb4u("frobnicate");
  EXPECT_NE(r.exit_code, 0);
}

}  // namespace
}  // namespace pb4u
