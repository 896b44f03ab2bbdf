// A body that crosses itself: two overlapping boxes, whose covered faces are known in closed form
// (a face is covered when its centroid lies inside the other box).
#include <gtest/gtest.h>

#include "pb4u/body/outer_faces.h"
#include "test_util.h"

namespace pb4u {
namespace {

TEST(OuterFaces, TheFacesInsideTheOtherPartAreCoveredTheRestAreOuter) {
  const TriMesh a = test::box_mesh({0, 0, 0}, {1, 1, 1});
  EXPECT_EQ(outer_faces(a.V, a.F), a.F);  // a closed surface that does not cross itself: all faces

  const Eigen::RowVector3d lo(0.8, 0.2, 0.2), hi(1.8, 0.8, 0.8);  // sticks out of a's x = 1 side
  const TriMesh ab = test::joined(a, test::box_mesh(lo, hi));
  const std::vector<char> covered = covered_faces(ab.V, ab.F);
  int expected_covered = 0;
  for (Eigen::Index f = 0; f < ab.F.rows(); ++f) {
    const Eigen::RowVector3d c = (ab.V.row(ab.F(f, 0)) + ab.V.row(ab.F(f, 1)) + ab.V.row(ab.F(f, 2))) / 3.0;
    const bool in_other = f < 12 ? (c.array() > lo.array()).all() && (c.array() < hi.array()).all()
                                 : (c.array() > 0).all() && (c.array() < 1).all();
    EXPECT_EQ(bool(covered[size_t(f)]), in_other) << "face " << f;
    expected_covered += in_other;
  }
  // The second box's x = 0.8 side lies inside the first, and the centroids of the first box's
  // x = 1 side inside the second: 2 faces each; the other 20 are outer.
  EXPECT_EQ(expected_covered, 4);
  EXPECT_EQ(outer_faces(ab.V, ab.F).rows(), 20);
}

}  // namespace
}  // namespace pb4u
