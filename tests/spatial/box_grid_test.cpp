// The box grid's queries against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

#include "pb4u/spatial/box_grid.h"

namespace pb4u {
namespace {

bool overlap(const Eigen::Vector3d& alo, const Eigen::Vector3d& ahi, const Eigen::Vector3d& blo,
             const Eigen::Vector3d& bhi) {
  return (alo.array() <= bhi.array()).all() && (ahi.array() >= blo.array()).all();
}

TEST(BoxGrid, EveryOverlappingBoxIsFoundOnceAndInOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), size(0.0, 0.05);
  // Small boxes, a few long ones (a body's sliver faces) and a point (a zero box).
  const int n = 600;
  Eigen::MatrixXd lo(n, 3), hi(n, 3);
  for (int i = 0; i < n; ++i) {
    const Eigen::RowVector3d c(u(rng), u(rng), 0.3 * u(rng));
    const Eigen::RowVector3d h(size(rng), size(rng), i % 50 == 0 ? 0.8 : size(rng));
    lo.row(i) = c - h;
    hi.row(i) = c + h;
  }
  lo.row(n - 1) = hi.row(n - 1);
  const BoxGrid grid(lo, hi);
  ASSERT_EQ(grid.size(), n);
  std::vector<int> near;
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d c(1.2 * u(rng), 1.2 * u(rng), 1.2 * u(rng));
    const double r = q % 10 == 0 ? 0.3 : 0.04 * std::abs(u(rng));
    grid.near_box(c.array() - r, c.array() + r, &near);
    EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
    EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end());
    for (int i = 0; i < n; ++i)
      if (overlap(c.array() - r, c.array() + r, lo.row(i).transpose(), hi.row(i).transpose()))
        EXPECT_TRUE(std::binary_search(near.begin(), near.end(), i)) << "query " << q << " box " << i;
  }
  // The point box, queried exactly where it is.
  grid.near_box(lo.row(n - 1).transpose(), hi.row(n - 1).transpose(), &near);
  EXPECT_TRUE(std::binary_search(near.begin(), near.end(), n - 1));
}

TEST(BoxGrid, QueriesAwayFromEveryBoxOrNotFiniteMeetNothing) {
  Eigen::MatrixXd lo(2, 3), hi(2, 3);
  lo << 0, 0, 0, 1, 1, 1;
  hi << 0.1, 0.1, 0.1, 1.1, 1.1, 1.1;
  const BoxGrid grid(lo, hi);
  std::vector<int> near{42};
  grid.near_box(Eigen::Vector3d::Constant(2), Eigen::Vector3d::Constant(3), &near);
  EXPECT_TRUE(near.empty());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  grid.near_box(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(nan, 1, 1), &near);
  EXPECT_TRUE(near.empty());
  grid.near_box(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(2), &near);
  EXPECT_EQ(near, (std::vector<int>{0, 1}));
  const BoxGrid empty(Eigen::MatrixXd(0, 3), Eigen::MatrixXd(0, 3));
  empty.near_box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), &near);
  EXPECT_TRUE(near.empty());
}

}  // namespace
}  // namespace pb4u
