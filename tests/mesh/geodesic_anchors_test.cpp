// The eslr baseline's geodesic anchors (mesh/geodesic_anchors.h) on graphs worked out by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pb4u/mesh/edges.h"
#include "pb4u/mesh/geodesic_anchors.h"
#include "pb4u/mesh/geometry.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

Eigen::MatrixXi edge_rows(std::initializer_list<std::pair<int, int>> pairs) {
  Eigen::MatrixXi E(static_cast<Eigen::Index>(pairs.size()), 2);
  int e = 0;
  for (auto [a, b] : pairs) E.row(e++) << a, b;
  return E;
}

// A path 0 -1- 1 -2- 2 -1- 3 -1- 4: the farthest from 0 is 4 (5 m), from 4 then 0, and from
// {4, 0} vertex 2 (3 m from 0, 2 m from 4: 2 m; vertex 1 and 3 are 1 m from an anchor).
TEST(GeodesicAnchors, FarthestPointSamplingAlongAWeightedPath) {
  const Eigen::MatrixXi E = edge_rows({{0, 1}, {1, 2}, {2, 3}, {3, 4}});
  const Eigen::VectorXd L = (Eigen::VectorXd(4) << 1, 2, 1, 1).finished();
  GeodesicAnchors a = geodesic_anchors(E, L, 5, 3);
  EXPECT_EQ(a.anchors, (std::vector<int>{4, 0, 2}));
  ASSERT_EQ(a.distance.rows(), 5);
  ASSERT_EQ(a.distance.cols(), 3);
  const Eigen::VectorXd from4 = (Eigen::VectorXd(5) << 5, 4, 2, 1, 0).finished();
  const Eigen::VectorXd from0 = (Eigen::VectorXd(5) << 0, 1, 3, 4, 5).finished();
  const Eigen::VectorXd from2 = (Eigen::VectorXd(5) << 3, 2, 0, 1, 2).finished();
  EXPECT_TRUE(a.distance.col(0).isApprox(from4));
  EXPECT_TRUE(a.distance.col(1).isApprox(from0));
  EXPECT_TRUE(a.distance.col(2).isApprox(from2));
}

// Two components, 0-1-2 and 3-4: the second anchor is the unreached component's lowest vertex,
// and distances across components are infinite.
TEST(GeodesicAnchors, EveryComponentGetsAnAnchorBeforeAnyGetsTwo) {
  const Eigen::MatrixXi E = edge_rows({{0, 1}, {1, 2}, {3, 4}});
  const Eigen::VectorXd L = Eigen::VectorXd::Ones(3);
  GeodesicAnchors a = geodesic_anchors(E, L, 5, 3);
  EXPECT_EQ(a.anchors, (std::vector<int>{2, 3, 0}));
  EXPECT_TRUE(std::isinf(a.distance(0, 1)));
  EXPECT_TRUE(std::isinf(a.distance(4, 0)));
  EXPECT_DOUBLE_EQ(a.distance(4, 1), 1.0);
  EXPECT_DOUBLE_EQ(a.distance(0, 0), 2.0);
}

// Asking for more anchors than vertices gives every vertex once, each at distance 0 from itself;
// on a grid the edge path matches the triangulation's (its diagonals included).
TEST(GeodesicAnchors, AtMostEveryVertexOnceAndSymmetricDistances) {
  TriMesh grid = test::grid_mesh(3, 0.3);  // 4 x 4 vertices, 10 cm cells
  const Eigen::MatrixXi E = unique_edges(grid.F);
  const Eigen::VectorXd L = edge_lengths(grid.V, E);
  GeodesicAnchors a = geodesic_anchors(E, L, 16, 100);
  ASSERT_EQ(a.anchors.size(), 16u);
  std::vector<int> sorted = a.anchors;
  std::sort(sorted.begin(), sorted.end());
  for (int v = 0; v < 16; ++v) EXPECT_EQ(sorted[static_cast<size_t>(v)], v);
  for (int k = 0; k < 16; ++k) {
    EXPECT_DOUBLE_EQ(a.distance(a.anchors[static_cast<size_t>(k)], k), 0.0);
    for (int j = 0; j < 16; ++j)  // d(anchor k, anchor j) read both ways
      EXPECT_NEAR(a.distance(a.anchors[static_cast<size_t>(j)], k), a.distance(a.anchors[static_cast<size_t>(k)], j), 1e-12);
  }
  // Opposite corners: three cells along and three across, so at least the straight line's
  // 0.424 m and at most the L-path's 0.6 m.
  const double corner = a.distance(15, std::find(a.anchors.begin(), a.anchors.end(), 0) - a.anchors.begin());
  EXPECT_GE(corner, std::sqrt(2.0) * 0.3 - 1e-12);
  EXPECT_LE(corner, 0.6 + 1e-12);
}

TEST(GeodesicAnchors, BadGraphsThrow) {
  const Eigen::MatrixXi E = edge_rows({{0, 1}, {1, 5}});
  EXPECT_THROW(geodesic_anchors(E, Eigen::VectorXd::Ones(2), 3, 2), Error);                      // index
  EXPECT_THROW(geodesic_anchors(edge_rows({{0, 1}}), -Eigen::VectorXd::Ones(1), 2, 2), Error);   // length
  EXPECT_THROW(geodesic_anchors(edge_rows({{0, 1}}), Eigen::VectorXd::Ones(2), 2, 2), Error);    // count
  EXPECT_EQ(geodesic_anchors(edge_rows({{0, 1}}), Eigen::VectorXd::Ones(1), 2, 0).anchors.size(), 0u);
}

}  // namespace
}  // namespace pb4u
