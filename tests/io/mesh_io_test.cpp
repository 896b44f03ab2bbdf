// Reading and writing meshes, on the shipped t-shirt and on generated grids.
#include <gtest/gtest.h>

#include <filesystem>

#include "pb4u/io/mesh_io.h"
#include "pb4u/io/mesh_summary.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

const std::string kTshirt = std::string(PB4U_TEST_DATA) + "/meshes/tshirt.obj";

TEST(MeshIo, TshirtHasFourOpeningsAndIsOneManifoldSurface) {
  MeshSummary s = summarize_mesh_file(kTshirt);
  EXPECT_EQ(s.vertices, 1386);
  EXPECT_EQ(s.faces, 2680);
  EXPECT_EQ(s.components, 1);
  EXPECT_EQ(s.boundary_loop_sizes.size(), 4u);  // neck, waist, two cuffs
  EXPECT_TRUE(s.manifold);
  EXPECT_TRUE(s.oriented);
  EXPECT_EQ(s.degenerate_faces, 0);
  // Euler: V - E + F = 2 - 2g - b with genus 0 and four boundaries.
  EXPECT_EQ(s.vertices - s.edges + s.faces, 2 - 4);
}

TEST(MeshIo, TriangleSoupWeldsBackToTheTshirt) {
  TriMesh shirt = read_mesh(kTshirt);
  // Explode: every face gets its own three vertices, written as a soup OBJ and a PLY.
  TriMesh soup;
  soup.V.resize(3 * shirt.num_faces(), 3);
  soup.F.resize(shirt.num_faces(), 3);
  for (int f = 0; f < shirt.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      soup.V.row(3 * f + k) = shirt.V.row(shirt.F(f, k));
      soup.F(f, k) = 3 * f + k;
    }
  std::string dir = test::temp_dir("soup");
  for (const char* name : {"/soup.obj", "/soup.ply"}) {
    write_mesh(dir + name, soup);
    MeshSummary s = summarize_mesh_file(dir + name);
    EXPECT_EQ(s.vertices, shirt.num_vertices()) << name;
    EXPECT_EQ(s.faces, shirt.num_faces()) << name;
    EXPECT_EQ(s.components, 1) << name;
    EXPECT_EQ(s.boundary_loop_sizes.size(), 4u) << name;
    EXPECT_TRUE(s.manifold) << name;
  }
}

TEST(MeshIo, ObjAndPlyRoundTrip) {
  TriMesh g = test::grid_mesh(3, 0.7);
  std::string dir = test::temp_dir("roundtrip");
  for (const char* name : {"/g.obj", "/g.ply"}) {
    write_mesh(dir + name, g);
    TriMesh back = read_mesh(dir + name);
    ASSERT_EQ(back.num_vertices(), g.num_vertices()) << name;
    ASSERT_EQ(back.num_faces(), g.num_faces()) << name;
    // Vertex numbering may change on import (welding renumbers in face order); faces keep
    // their order and corner order, so compare corner positions.
    for (int f = 0; f < g.num_faces(); ++f)
      for (int k = 0; k < 3; ++k)
        EXPECT_LT((back.V.row(back.F(f, k)) - g.V.row(g.F(f, k))).norm(), 1e-6) << name;
  }
  // No temporaries left next to the outputs.
  int files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 2);
}

TEST(MeshIo, UnknownOutputExtensionLeavesNothingBehind) {
  std::string dir = test::temp_dir("ext");
  EXPECT_THROW(write_mesh(dir + "/g.fbx", test::grid_mesh(1)), Error);
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(MeshIo, AsciiStlImport) {
  // An STL is a triangle soup by definition: it must weld into one quad.
  std::string dir = test::temp_dir("formats");
  test::write_file(dir + "/q.stl",
                   "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                   "vertex 1 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n"
                   "vertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid q\n");
  TriMesh q = read_mesh(dir + "/q.stl");
  EXPECT_EQ(q.num_vertices(), 4);
  EXPECT_EQ(q.num_faces(), 2);
}

}  // namespace
}  // namespace pb4u
