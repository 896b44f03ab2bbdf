// KD-tree queries against brute force.
#include <gtest/gtest.h>

#include <random>

#include "pb4u/spatial/point_kd_tree.h"

namespace pb4u {
namespace {

Eigen::MatrixXd random_points(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd P(n, 3);
  for (int i = 0; i < n; ++i) P.row(i) << u(rng), u(rng), u(rng);
  return P;
}

TEST(PointKdTree, NearestMatchesBruteForce) {
  Eigen::MatrixXd P = random_points(500, 1), Q = random_points(200, 2);
  PointKdTree tree(P);
  Eigen::VectorXi idx;
  Eigen::VectorXd d2;
  tree.nearest(Q, &idx, &d2);
  for (int q = 0; q < Q.rows(); ++q) {
    Eigen::Index best;
    double bd = (P.rowwise() - Q.row(q)).rowwise().squaredNorm().minCoeff(&best);
    EXPECT_EQ(idx(q), best);
    EXPECT_NEAR(d2(q), bd, 1e-12);
  }
}

TEST(PointKdTree, RadiusMatchesBruteForce) {
  Eigen::MatrixXd P = random_points(400, 3), Q = random_points(100, 4);
  PointKdTree tree(P);
  const double r = 0.2;
  auto pairs = tree.within_radius(Q, r);
  std::vector<std::pair<int, int>> expected;
  for (int q = 0; q < Q.rows(); ++q)
    for (int p = 0; p < P.rows(); ++p)
      if ((P.row(p) - Q.row(q)).norm() < r) expected.emplace_back(q, p);
  EXPECT_EQ(pairs, expected);
  // One query at a time, each with its own radius.
  for (int q = 0; q < Q.rows(); ++q) {
    const double rq = 0.05 + 0.003 * q;
    std::vector<int> one;
    for (int p = 0; p < P.rows(); ++p)
      if ((P.row(p) - Q.row(q)).norm() < rq) one.push_back(p);
    EXPECT_EQ(tree.within_radius_of(Q.row(q).transpose(), rq), one) << q;
  }
}

TEST(PointKdTree, EmptySet) {
  PointKdTree tree(Eigen::MatrixXd(0, 3));
  Eigen::VectorXi idx;
  tree.nearest(random_points(3, 5), &idx);
  EXPECT_EQ(idx(0), -1);
  EXPECT_TRUE(tree.within_radius(random_points(3, 5), 1.0).empty());
  EXPECT_TRUE(tree.within_radius_of(Eigen::Vector3d::Zero(), 1.0).empty());
}

}  // namespace
}  // namespace pb4u
