// spatial/points_over_faces.h on one triangle worked by hand.
#include <gtest/gtest.h>

#include "pb4u/spatial/points_over_faces.h"

namespace pb4u {
namespace {

// The triangle (0,0,0), (1,0,0), (0,0,1): normal (1,0,0) x (0,0,1) = (0,-1,0).
TEST(PointsOverFaces, InsideWithinTheRadiusOnlyAndSigned) {
  Eigen::MatrixXd V(3, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 0, 1;
  Eigen::MatrixXi F(1, 3);
  F << 0, 1, 2;
  Eigen::MatrixXd points(4, 3);
  points << 0.2, 0.005, 0.2,  // over it, 5 mm on the +y side: d = -0.005
      0.2, -0.02, 0.2,        // 2 cm under it: beyond the radius
      0.8, 0.001, 0.8,        // 1 mm off the plane but outside the triangle (u + v = 1.6)
      0.0, -0.001, 0.5;       // on the edge x = 0, 1 mm below: d = +0.001
  const auto pairs = points_over_faces(points, V, F, 0.01, false);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].point, 0);
  EXPECT_NEAR(pairs[0].distance, -0.005, 1e-15);
  EXPECT_EQ(pairs[1].point, 3);
  EXPECT_NEAR(pairs[1].distance, 0.001, 1e-15);
  // The mesh's own vertices lie on the face but hold it: no pair.
  EXPECT_TRUE(points_over_faces(V, V, F, 0.01, true).empty());
  EXPECT_TRUE(points_over_faces(points, V, Eigen::MatrixXi(0, 3), 0.01, false).empty());
}

}  // namespace
}  // namespace pb4u
