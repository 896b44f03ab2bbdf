// HOOD's coarse levels (mesh/coarse_levels.h) against graphs worked out by hand.
#include <gtest/gtest.h>

#include <queue>
#include <set>

#include "pb4u/mesh/coarse_levels.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

// Breadth-first hops between a and b over the edges E.
int hops(const Eigen::MatrixXi& E, int n, int a, int b) {
  std::vector<std::vector<int>> adj(n);
  for (int e = 0; e < E.rows(); ++e) {
    adj[E(e, 0)].push_back(E(e, 1));
    adj[E(e, 1)].push_back(E(e, 0));
  }
  std::vector<int> d(n, -1);
  std::queue<int> q;
  d[a] = 0;
  q.push(a);
  while (!q.empty()) {
    int v = q.front();
    q.pop();
    for (int w : adj[v])
      if (d[w] < 0) d[w] = d[v] + 1, q.push(w);
  }
  return d[b];
}

std::set<int> vertices_of(const Eigen::MatrixXi& E) {
  std::set<int> out;
  for (int e = 0; e < E.rows(); ++e) out.insert({E(e, 0), E(e, 1)});
  return out;
}

Eigen::MatrixXi path_edges(int first, int count) {
  Eigen::MatrixXi E(count - 1, 2);
  for (int i = 0; i + 1 < count; ++i) E.row(i) << first + i, first + i + 1;
  return E;
}

// A path 0-1-2-3-4: centre 2; odd vertices 1 and 3 join 2 to 0 and 2 to 4; on that graph the
// ends are at odd distance with nothing beyond, so level 1 is empty.
TEST(CoarseLevels, PathByHand) {
  CoarseLevels c = coarse_levels(path_edges(0, 5), 5, 2);
  EXPECT_EQ(c.centers, std::vector<int>{2});
  Eigen::MatrixXi level0(2, 2);
  level0 << 0, 2, 2, 4;
  EXPECT_EQ(c.edges[0], level0);
  EXPECT_EQ(c.edges[1].rows(), 0);
  EXPECT_EQ(c.vertex_level, (Eigen::VectorXi(5) << 1, 0, 1, 0, 1).finished());
}

// The 5 x 5 grid (test::grid_mesh(4): vertex 5i + j, each quad split by its (i, j+1)-(i+1, j)
// diagonal). Hops between (i, j) and (i', j'): max(|di|, |dj|) when di and dj have opposite
// signs, |di| + |dj| otherwise. Corners (0, 0) and (4, 4) are 8 apart, so no vertex has
// eccentricity below 4, and the five on the anti-diagonal i + j = 4 have exactly 4: the centre
// is the lowest-index one, vertex 4 = (0, 4). From it, hops are max(i, 4 - j): shells of 1, 3,
// 5, 7 and 9 vertices. Level 0 keeps the even shells (1 + 5 + 9 = 15 vertices), its edges
// joining vertices two hops apart; on level 0 the 5-vertex shell is at distance 1, so level 1
// joins the centre to the 9 vertices 4 hops out; level 1 is a star, and level 2 is empty.
TEST(CoarseLevels, GridByHand) {
  TriMesh grid = test::grid_mesh(4);
  Eigen::MatrixXi E = unique_edges(grid.F);
  CoarseLevels c = coarse_levels(E, 25, 3);
  EXPECT_EQ(c.centers, std::vector<int>{4});
  ASSERT_EQ(c.edges.size(), 3u);
  EXPECT_EQ(vertices_of(c.edges[0]).size(), 15u);
  EXPECT_EQ(vertices_of(c.edges[1]).size(), 10u);
  EXPECT_EQ(c.edges[2].rows(), 0);
  for (int v : vertices_of(c.edges[0])) EXPECT_EQ(std::max(v / 5, 4 - v % 5) % 2, 0) << v;
  // Spans: level 0's edges 2 hops on the mesh, level 1's 4 (centre to the outer shell).
  EXPECT_EQ(c.edges[0].rows(), 22);
  for (int e = 0; e < c.edges[0].rows(); ++e) EXPECT_EQ(hops(E, 25, c.edges[0](e, 0), c.edges[0](e, 1)), 2);
  EXPECT_EQ(c.edges[1].rows(), 9);
  for (int e = 0; e < c.edges[1].rows(); ++e) {
    const int a = c.edges[1](e, 0), b = c.edges[1](e, 1);
    ASSERT_TRUE(a == 4 || b == 4) << a << "-" << b;
    EXPECT_EQ(hops(E, 25, a, b), 4);
  }
  Eigen::VectorXi level(25);
  level << 2, 0, 1, 0, 2,  //
      2, 0, 1, 0, 0,       //
      2, 0, 1, 1, 1,       //
      2, 0, 0, 0, 0,       //
      2, 2, 2, 2, 2;
  EXPECT_EQ(c.vertex_level, level);
}

TEST(CoarseLevels, EachComponentHasItsCentre) {
  Eigen::MatrixXi E(8, 2);
  E << path_edges(0, 5), path_edges(10, 5);  // vertices 5-9 are isolated
  CoarseLevels c = coarse_levels(E, 15, 1);
  EXPECT_EQ(c.centers, (std::vector<int>{2, 12}));
  Eigen::MatrixXi level0(4, 2);
  level0 << 0, 2, 2, 4, 10, 12, 12, 14;
  EXPECT_EQ(c.edges[0], level0);
  for (int v = 5; v < 10; ++v) EXPECT_EQ(c.vertex_level(v), 0);
}

TEST(CoarseLevels, CentreIsTheLowestIndexOfLeastEccentricity) {
  // A path of 6: eccentricities 5 4 3 3 4 5.
  std::vector<std::vector<int>> path(6);
  for (int i = 0; i + 1 < 6; ++i) path[i].push_back(i + 1), path[i + 1].push_back(i);
  EXPECT_EQ(graph_center(path, 5), 2);
  // A star with a long arm: 0 is the hub of 1, 2, 3; the arm 3-4-5-6 pulls the centre to 3.
  std::vector<std::vector<int>> star(7);
  for (auto [a, b] : std::vector<std::pair<int, int>>{{0, 1}, {0, 2}, {0, 3}, {3, 4}, {4, 5}, {5, 6}})
    star[a].push_back(b), star[b].push_back(a);
  EXPECT_EQ(graph_center(star, 1), 3);
}

TEST(CoarseLevels, BadInputIsAClearError) {
  Eigen::MatrixXi E(1, 2);
  E << 0, 7;
  EXPECT_THROW(coarse_levels(E, 5, 1), Error);
  EXPECT_THROW(coarse_levels(path_edges(0, 3), 3, -1), Error);
}

}  // namespace
}  // namespace pb4u
