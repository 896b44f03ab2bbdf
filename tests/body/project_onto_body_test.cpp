// Which side of a body a point is on, where the nearest face's side says otherwise: a body of two
// overlapping boxes (a forearm in a hip), the point inside the first and nearest to the second's
// face that lies inside the first.
#include <gtest/gtest.h>

#include "pb4u/body/project_onto_body.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(ProjectOntoBody, ThePointInsideOnePartNearestAnotherPartsFaceIsInside) {
  const TriMesh body = test::joined(test::box_mesh({0, 0, 0}, {1, 1, 1}), test::box_mesh({0.8, 0.2, 0.2}, {1.8, 0.8, 0.8}));
  Eigen::MatrixXd p(1, 3);
  p << 0.75, 0.5, 0.5;  // inside the first box, 5 cm in front of the second box's x = 0.8 side
  const SurfaceProjection nearest_side = project_onto_surface(p, body.V, body.F);
  EXPECT_NEAR(nearest_side.distance(0), 0.05, 1e-12);  // what the pseudo-normal reads: outside
  const SurfaceProjection q = project_onto_body(p, body.V, body.F);
  EXPECT_LT(q.distance(0), 0);
  // The distance is to the faces no part covers: the second box's x = 0.8 side is left out.
  EXPECT_GT(-q.distance(0), 0.05 + 1e-6);
  EXPECT_NEAR(-q.distance(0), (q.closest.row(0) - p.row(0)).norm(), 1e-12);
  // Inside, out is from the point towards its closest point.
  EXPECT_NEAR(q.outward.row(0).dot((q.closest.row(0) - p.row(0)).normalized()), 1.0, 1e-12);
}

TEST(ProjectOntoBody, WhereTheNearestFaceIsRightItReadsAsTheSurfaceQueryDoes) {
  const TriMesh body = test::box_mesh({0, 0, 0}, {1, 1, 1});
  Eigen::MatrixXd p(3, 3);
  p << 0.5, 0.5, 1.2,  // 2 dm above the top
      0.5, 0.5, 0.9,   // 1 dm below it, inside
      0.5, 0.5, 1.0;   // on it
  const SurfaceProjection a = project_onto_surface(p, body.V, body.F), b = project_onto_body(p, body.V, body.F);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(a.distance(k), b.distance(k), 1e-12) << k;
    EXPECT_NEAR((a.outward.row(k) - b.outward.row(k)).norm(), 0, 1e-12) << k;
  }
  EXPECT_NEAR(b.distance(1), -0.1, 1e-12);
  EXPECT_NEAR(b.outward(1, 2), 1.0, 1e-12);  // up, out of the box
}

}  // namespace
}  // namespace pb4u
