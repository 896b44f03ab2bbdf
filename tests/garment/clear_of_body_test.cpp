// A garment's rest mesh cleared of its body (garment/clear_of_body.h): a square sleeve round a
// round arm, whose chords cut it, comes off it by the clearance; a sleeve that clears the arm
// is left bit for bit; a patch through the arm comes out of it.
#include <gtest/gtest.h>

#include <cmath>

#include "pb4u/garment/clear_of_body.h"
#include "pb4u/mesh/edges.h"
#include "pb4u/spatial/segments_through_surface.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "test_util.h"

namespace pb4u {
namespace {

constexpr double kArm = 0.04;  // m, the arm's radius

// A closed, outward "arm": a prism of `sides` sides round the x axis, radius r, x in [-L, L].
TriMesh arm(double r = kArm, int sides = 48, double L = 0.3) {
  TriMesh m;
  m.V.resize(2 * sides + 2, 3);
  for (int e = 0; e < 2; ++e)
    for (int j = 0; j < sides; ++j) {
      const double a = 2 * M_PI * j / sides;
      m.V.row(e * sides + j) << (e ? L : -L), r * std::cos(a), r * std::sin(a);
    }
  m.V.row(2 * sides) << -L, 0, 0;
  m.V.row(2 * sides + 1) << L, 0, 0;
  m.F.resize(4 * sides, 3);
  for (int j = 0; j < sides; ++j) {
    const int a = j, b = (j + 1) % sides, c = sides + j, d = sides + (j + 1) % sides;
    m.F.row(4 * j) << a, b, c;  // (b - a) x (c - a) points away from the axis
    m.F.row(4 * j + 1) << b, d, c;
    m.F.row(4 * j + 2) << 2 * sides, b, a;
    m.F.row(4 * j + 3) << 2 * sides + 1, c, d;
  }
  return m;
}

// A tube of `rings` rings of `sides` vertices at radius R round the x axis, 5 cm apart: a sleeve.
TriMesh sleeve(double R, int sides, int rings = 3) {
  TriMesh m;
  m.V.resize(rings * sides, 3);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const double a = 2 * M_PI * (j + 0.5) / sides;
      m.V.row(i * sides + j) << 0.05 * (i - (rings - 1) / 2.0), R * std::cos(a), R * std::sin(a);
    }
  m.F.resize(2 * (rings - 1) * sides, 3);
  for (int i = 0; i + 1 < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const int a = i * sides + j, b = i * sides + (j + 1) % sides, c = a + sides, d = b + sides;
      m.F.row(2 * (i * sides + j)) << a, b, c;
      m.F.row(2 * (i * sides + j) + 1) << b, d, c;
    }
  return m;
}

// A square of n x n cells, `size` m wide, centred on `centre`, in the plane normal to axis
// `normal` (0: x, 1: y, 2: z).
TriMesh square(int n, double size, int normal, const Eigen::RowVector3d& centre) {
  TriMesh m = test::grid_mesh(n, size);  // xz plane at y = 0, [0, size]^2
  m.V.col(0).array() -= size / 2;
  m.V.col(2).array() -= size / 2;
  if (normal != 1) m.V.col(1).swap(m.V.col(normal));
  m.V.rowwise() += centre;
  return m;
}

int edges_through(const TriMesh& garment, const TriMesh& body) {
  return int(segments_through_surface(garment.V, unique_edges(garment.F), body.V, body.F).size());
}

TEST(ClearOfBody, ASquareSleeveRoundARoundArmComesOffItByTheClearance) {
  const TriMesh body = arm();
  // Corners 5 mm off the arm: the chords' middles are 0.045 cos 45 = 32 mm from the axis, 8 mm
  // inside the arm.
  TriMesh garment = sleeve(kArm + 0.005, 4);
  // The rings' 12 sides and the 8 diagonals between rings; the 8 edges along the arm clear it.
  ASSERT_EQ(edges_through(garment, body), 20);
  const double clearance = 0.003;
  const BodyClearance c = clear_of_body(garment, body, clearance);
  EXPECT_EQ(c.edges_through_before, 20);
  EXPECT_TRUE(c.clear());
  EXPECT_EQ(edges_through(garment, body), 0);
  EXPECT_EQ(c.moved, 12);
  EXPECT_EQ(c.folded_faces, 0);  // the sleeve widened, not folded
  // Every point of every edge, not only the vertices, at least the clearance off the arm (to
  // the edge's sampling: 15 points between its ends).
  const Eigen::MatrixXi E = unique_edges(garment.F);
  Eigen::MatrixXd points(E.rows() * 101, 3);
  for (Eigen::Index e = 0; e < E.rows(); ++e)
    for (int k = 0; k <= 100; ++k)
      points.row(e * 101 + k) = garment.V.row(E(e, 0)) + (k / 100.0) * (garment.V.row(E(e, 1)) - garment.V.row(E(e, 0)));
  EXPECT_GT(signed_distance_to_surface(points, body.V, body.F).minCoeff(), 0.0);
  EXPECT_GE(signed_distance_to_surface(garment.V, body.V, body.F).minCoeff(), clearance * (1 - 1e-6));
  // The smallest square whose sides clear a circle of radius r + clearance has its corners at
  // sqrt(2) (r + clearance) from the centre: the sleeve is not moved far beyond that.
  const double needed = std::sqrt(2.0) * (kArm + clearance);
  for (Eigen::Index i = 0; i < garment.V.rows(); ++i)
    EXPECT_LT(garment.V.row(i).tail<2>().norm(), 1.5 * needed) << "vertex " << i;
}

TEST(ClearOfBody, ASleeveThatClearsTheArmIsLeftBitForBit) {
  const TriMesh body = arm();
  TriMesh garment = sleeve(kArm + 0.01, 12);  // chords' middles at 0.05 cos 15 = 48 mm: 8 mm off
  const TriMesh before = garment;
  const BodyClearance c = clear_of_body(garment, body, 0.003);
  EXPECT_EQ(c.edges_through_before, 0);
  EXPECT_EQ(c.moved, 0);
  EXPECT_TRUE(c.clear());
  EXPECT_TRUE(garment.V == before.V);
  EXPECT_TRUE(garment.F == before.F);
}

TEST(ClearOfBody, APatchThroughTheArmComesOutOfIt) {
  const TriMesh body = arm();
  // A 3 x 3 patch in the plane z = 0.02, half inside the arm (|y| < 0.035 there is inside).
  TriMesh garment = square(2, 0.1, 2, {0, 0, 0.02});
  ASSERT_LT(signed_distance_to_surface(garment.V, body.V, body.F).minCoeff(), -0.01);
  const BodyClearance c = clear_of_body(garment, body, 0.002);
  EXPECT_TRUE(c.clear());
  EXPECT_GE(signed_distance_to_surface(garment.V, body.V, body.F).minCoeff(), 0.002 * (1 - 1e-6));
  EXPECT_EQ(edges_through(garment, body), 0);
  EXPECT_GT(c.largest_move, 0.02);  // the middle row came up through the arm's top
}

TEST(ClearOfBody, AWallTheArmPassesThroughIsFoldedAndSaysSo) {
  const TriMesh body = arm();
  // A 5 x 5 wall in the plane x = 0 through which the arm (along x) passes, as a boxy garment
  // file's sleeve wall that a lowered arm pierces: its vertices go out on every side of the arm
  // and the faces between them turn over. The count says the garment does not fit the body.
  TriMesh garment = square(4, 0.16, 0, {0, 0, 0});
  ASSERT_LT(signed_distance_to_surface(garment.V, body.V, body.F).minCoeff(), -0.03);
  const BodyClearance c = clear_of_body(garment, body, 0.003);
  EXPECT_GT(c.folded_faces, 0);
}

}  // namespace
}  // namespace pb4u
