// Winding numbers of closed surfaces against what a box and two overlapping boxes enclose, with
// rays along the boxes' own edges and triangle diagonals (where a careless ray counts twice).
#include <gtest/gtest.h>

#include "pb4u/spatial/winding_number.h"
#include "pb4u/util/error.h"
#include "test_util.h"

namespace pb4u {
namespace {

Eigen::MatrixXd rows(std::initializer_list<Eigen::RowVector3d> points) {
  Eigen::MatrixXd out(Eigen::Index(points.size()), 3);
  Eigen::Index i = 0;
  for (const auto& p : points) out.row(i++) = p;
  return out;
}

TEST(WindingNumbers, ABoxWrapsItsInsideOnceAndTwoOverlappingBoxesTheirOverlapTwice) {
  const TriMesh a = test::box_mesh({0, 0, 0}, {1, 1, 1});
  const Eigen::MatrixXd inside_and_out = rows({{0.5, 0.5, 0.5}, {-0.5, 0.5, 0.5}, {1.5, 0.5, 0.5}, {0.5, 2, 0.5}});
  EXPECT_EQ(WindingNumbers(a.V, a.F).at(inside_and_out), Eigen::Vector4i(1, 0, 0, 0));
  // The ray in +x along a side's diagonal (y = z, where its two triangles meet), along an edge of
  // the box (y = z = 0) and through a corner: each inside point once, each outside point zero.
  const Eigen::MatrixXd on_lines = rows({{0.5, 0.3, 0.3}, {-1, 0.3, 0.3}, {0.5, 0.0, 0.0}, {-1, 0.0, 0.0}, {0.5, 1, 1}});
  const Eigen::VectorXi w = WindingNumbers(a.V, a.F).at(on_lines);
  EXPECT_EQ(w(0), 1);
  EXPECT_EQ(w(1), 0);
  EXPECT_EQ(w(3), 0);
  // On the box's own edges the point is on the surface: either side, but never counted twice.
  EXPECT_TRUE(w(2) == 0 || w(2) == 1) << w(2);
  EXPECT_TRUE(w(4) == 0 || w(4) == 1) << w(4);

  // A second box overlapping the first over x in [0.8, 1]: 2 in the overlap, 1 in either alone.
  const TriMesh ab = test::joined(a, test::box_mesh({0.8, 0, 0}, {1.8, 1, 1}));
  const Eigen::MatrixXd across = rows({{0.5, 0.5, 0.5}, {0.9, 0.5, 0.5}, {1.5, 0.5, 0.5}, {2.5, 0.5, 0.5}});
  EXPECT_EQ(WindingNumbers(ab.V, ab.F).at(across), Eigen::Vector4i(1, 2, 1, 0));

  // Inward faces wrap negatively.
  Eigen::MatrixXi inward = a.F;
  inward.col(1).swap(inward.col(2));
  EXPECT_EQ(WindingNumbers(a.V, inward).at(rows({{0.5, 0.5, 0.5}}))(0), -1);
}

TEST(WindingNumbers, BadSurfacesAreRefused) {
  const TriMesh a = test::box_mesh({0, 0, 0}, {1, 1, 1});
  EXPECT_THROW(WindingNumbers(Eigen::MatrixXd(0, 3), a.F), Error);
  Eigen::MatrixXi out_of_range = a.F;
  out_of_range(0, 0) = 8;
  EXPECT_THROW(WindingNumbers(a.V, out_of_range), Error);
  Eigen::MatrixXd nan = a.V;
  nan(0, 0) = std::nan("");
  EXPECT_THROW(WindingNumbers(nan, a.F), Error);
}

}  // namespace
}  // namespace pb4u
