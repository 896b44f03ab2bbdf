// Closed-form checks of the mesh core.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "pb4u/mesh/clean.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/mesh/rest_frames.h"
#include "pb4u/mesh/topology.h"
#include "mesh/corner_tetrahedron.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(MeshCore, GridCountsFollowEuler) {
  TriMesh g = test::grid_mesh(4);
  EXPECT_EQ(g.num_vertices(), 25);
  EXPECT_EQ(g.num_faces(), 32);
  // E = V + F - 1 for a disc (Euler characteristic 1).
  EXPECT_EQ(unique_edges(g.F).rows(), 25 + 32 - 1);
  EXPECT_EQ(interior_hinges(g.F).size(), 56 - 16);  // all edges minus the 16 on the border
}

TEST(MeshCore, FaceAreasAndMassesSumToClosedForm) {
  TriMesh g = test::grid_mesh(5, 2.0);
  EXPECT_NEAR(face_areas(g.V, g.F).sum(), 4.0, 1e-12);
  const double density = 0.20022;
  Eigen::VectorXd m = vertex_masses(g.V, g.F, density);
  EXPECT_NEAR(m.sum(), density * 4.0, 1e-12);
  // A corner vertex of the a,c,b / b,c,d split touches one triangle at (0,0): area h^2/2.
  const double h = 2.0 / 5;
  EXPECT_NEAR(m(0), density * h * h / 2 / 3, 1e-12);
}

TEST(MeshCore, NormalsOfTheGridPointUp) {
  TriMesh g = test::grid_mesh(3);
  Eigen::MatrixXd N = vertex_normals(g.V, g.F);
  for (int v = 0; v < N.rows(); ++v) {
    EXPECT_NEAR(N(v, 1), 1.0, 1e-12);
    EXPECT_NEAR(N.row(v).norm(), 1.0, 1e-12);
  }
}

TEST(MeshCore, MeanEdgeLengthOfGrid) {
  // n x n grid of size 1: 2n(n+1) axis edges of length 1/n and n^2 diagonals of sqrt(2)/n.
  const int n = 4;
  TriMesh g = test::grid_mesh(n);
  double axis = 2.0 * n * (n + 1), diag = n * n;
  double expected = (axis / n + diag * std::sqrt(2.0) / n) / (axis + diag);
  EXPECT_NEAR(mean_edge_length(g.V, g.F), expected, 1e-12);
  // Scaling the mesh scales the mean edge length.
  g.V *= 3.0;
  EXPECT_NEAR(mean_edge_length(g.V, g.F), 3.0 * expected, 1e-12);
}

TEST(MeshCore, VertexMeanEdgeLengthAtCorner) {
  TriMesh g = test::grid_mesh(2, 1.0);
  Eigen::VectorXd l = vertex_mean_edge_length(g.V, g.F);
  // Vertex 0 has two axis edges of length 0.5 (its diagonal goes from b to c, not through it).
  EXPECT_NEAR(l(0), 0.5, 1e-12);
  // Vertex 1 (b of the first cell): edges to 0, 2 (0.5), to 4 (0.5), to 3 (diagonal).
  EXPECT_NEAR(l(1), (0.5 * 3 + std::sqrt(0.5)) / 4, 1e-12);
}

TEST(MeshCore, DmInverseMapsRestEdgesToIdentity) {
  TriMesh m;
  m.V.resize(3, 3);
  m.V << 0.1, 0.2, 0.3, 0.6, 0.1, 0.4, 0.2, 0.9, 0.1;
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  Eigen::MatrixXd inv = rest_dm_inverse(m.V, m.F);
  Eigen::Matrix2d Dm_inv;
  Dm_inv << inv(0, 0), inv(0, 1), inv(0, 2), inv(0, 3);
  // Ds at rest in the same local frame equals Dm, so the 2D deformation gradient is I and
  // |det Dm| equals twice the area.
  Eigen::Vector3d e1 = m.V.row(1) - m.V.row(0), e2 = m.V.row(2) - m.V.row(0);
  double area = 0.5 * e1.cross(e2).norm();
  EXPECT_NEAR(1.0 / std::abs(Dm_inv.determinant()), 2 * area, 1e-12);
  // F = Ds Dm^-1 with 3D Ds: F^T F is the identity at rest.
  Eigen::Matrix<double, 3, 2> Ds;
  Ds << e1, e2;
  Eigen::Matrix<double, 3, 2> F = Ds * Dm_inv;
  EXPECT_TRUE((F.transpose() * F).isApprox(Eigen::Matrix2d::Identity(), 1e-12));
}

TEST(MeshCore, DegenerateFaceHasZeroDmInverse) {
  TriMesh m;
  m.V.resize(3, 3);
  m.V << 0, 0, 0, 1, 0, 0, 2, 0, 0;  // collinear
  m.F.resize(1, 3);
  m.F << 0, 1, 2;
  EXPECT_EQ(rest_dm_inverse(m.V, m.F).norm(), 0.0);
}

TEST(MeshCore, HingeOppositeVertices) {
  TriMesh m;
  m.V.resize(4, 3);
  m.V << 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 1;
  m.F.resize(2, 3);
  m.F << 0, 2, 1, 1, 2, 3;
  HingeSet h = interior_hinges(m.F);
  ASSERT_EQ(h.size(), 1);
  EXPECT_EQ(std::min(h.edge(0, 0), h.edge(0, 1)), 1);
  EXPECT_EQ(std::max(h.edge(0, 0), h.edge(0, 1)), 2);
  EXPECT_EQ(h.opposite(0, 0) + h.opposite(0, 1), 0 + 3);
  // The first face traverses edge(0) in order.
  int f0 = h.faces(0, 0);
  bool found = false;
  for (int c = 0; c < 3; ++c)
    found |= m.F(f0, c) == h.edge(0, 0) && m.F(f0, (c + 1) % 3) == h.edge(0, 1);
  EXPECT_TRUE(found);
}

TEST(MeshCore, TopologyOfClosedAndOpenSurfaces) {
  TriMesh t = test::corner_tetrahedron();
  EXPECT_TRUE(boundary_loops(t.F).empty());
  ManifoldReport r = check_manifold(t.F, 4);
  EXPECT_TRUE(r.manifold());
  EXPECT_TRUE(r.oriented());

  TriMesh g = test::grid_mesh(3);
  auto loops = boundary_loops(g.F);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 12u);
  int count = 0;
  connected_components(g.F, g.num_vertices(), &count);
  EXPECT_EQ(count, 1);
}

TEST(MeshCore, DetectsNonManifoldEdgeVertexAndFlippedFace) {
  TriMesh t = test::corner_tetrahedron();
  // A third face on edge (0, 1): non-manifold edge.
  TriMesh fin = t;
  fin.V.conservativeResize(5, 3);
  fin.V.row(4) << 0.5, -1, 0;
  fin.F.conservativeResize(5, 3);
  fin.F.row(4) << 0, 1, 4;
  EXPECT_EQ(check_manifold(fin.F, 5).nonmanifold_edges, 1);

  // Two tetrahedra sharing only vertex 0: a non-manifold (bow-tie) vertex.
  TriMesh bow;
  bow.V.resize(7, 3);
  bow.V.topRows(4) = t.V;
  bow.V.bottomRows(3) = -t.V.bottomRows(3);
  bow.F.resize(8, 3);
  bow.F.topRows(4) = t.F;
  bow.F.bottomRows(4) << 0, 5, 4, 0, 4, 6, 0, 6, 5, 4, 5, 6;
  ManifoldReport r = check_manifold(bow.F, 7);
  EXPECT_EQ(r.nonmanifold_edges, 0);
  EXPECT_EQ(r.nonmanifold_vertices, 1);
  int count = 0;
  connected_components(bow.F, 7, &count);
  EXPECT_EQ(count, 1);

  TriMesh flipped = t;
  std::swap(flipped.F(0, 1), flipped.F(0, 2));
  EXPECT_EQ(check_manifold(flipped.F, 4).misoriented_edges, 3);
}

TEST(MeshCore, TwoComponents) {
  TriMesh a = test::corner_tetrahedron();
  TriMesh both;
  both.V.resize(8, 3);
  both.V << a.V, (a.V.array() + 5.0).matrix();
  both.F.resize(8, 3);
  both.F << a.F, (a.F.array() + 4).matrix();
  int count = 0;
  Eigen::VectorXi label = connected_components(both.F, 8, &count);
  EXPECT_EQ(count, 2);
  EXPECT_NE(label(0), label(4));
}

TEST(MeshClean, WeldsATriangleSoupBackToTheSurface) {
  TriMesh g = test::grid_mesh(4);
  TriMesh soup;
  soup.V.resize(g.num_faces() * 3, 3);
  soup.F.resize(g.num_faces(), 3);
  for (int f = 0; f < g.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      // Perturb below the tolerance: welding must still merge.
      soup.V.row(3 * f + k) = g.V.row(g.F(f, k)).array() + 1e-9 * ((f + k) % 3);
      soup.F(f, k) = 3 * f + k;
    }
  CleanReport r = clean_mesh(soup, 1e-6);
  EXPECT_EQ(soup.num_vertices(), g.num_vertices());
  EXPECT_EQ(r.welded_vertices, 3 * g.num_faces() - g.num_vertices());
  EXPECT_EQ(unique_edges(soup.F).rows(), unique_edges(g.F).rows());
  int count = 0;
  connected_components(soup.F, soup.num_vertices(), &count);
  EXPECT_EQ(count, 1);
  EXPECT_EQ(boundary_loops(soup.F).size(), 1u);
}

TEST(MeshClean, DropsDegenerateDuplicateAndUnreferenced) {
  TriMesh m = test::grid_mesh(1);  // 4 vertices, 2 faces
  m.V.conservativeResize(6, 3);
  m.V.row(4) << 9, 9, 9;  // unreferenced
  m.V.row(5) << 0.5, 0, 0;  // collinear with 0 and 1
  m.F.conservativeResize(5, 3);
  m.F.row(2) << 0, 0, 1;  // repeated index
  m.F.row(3) << 0, 5, 1;  // zero area
  m.F.row(4) = m.F.row(0);  // duplicate
  CleanReport r = clean_mesh(m);
  EXPECT_EQ(r.removed_faces, 3);
  EXPECT_EQ(r.removed_vertices, 2);
  EXPECT_EQ(m.num_faces(), 2);
  EXPECT_EQ(m.num_vertices(), 4);
}

TEST(MeshClean, TriangulatesPolygonsAsFans) {
  Eigen::MatrixXi F = triangulate_polygons({{0, 1, 2, 3}, {4, 5}, {6, 7, 8, 9, 10}});
  ASSERT_EQ(F.rows(), 2 + 3);
  EXPECT_EQ(F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(F.row(4), Eigen::RowVector3i(6, 9, 10));
}

}  // namespace
}  // namespace pb4u
