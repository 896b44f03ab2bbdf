// Signed distance to a body surface and the penetration figures, against closed forms: a
// tetrahedron (faces, edges and corners: the pseudo-normal signs), a finely tessellated sphere
// (distance r - R for points at radius r) and brute force over every face.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pb4u/mesh/closest_point_on_triangle.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/util/error.h"
#include "mesh/corner_tetrahedron.h"
#include "physics_test_util.h"

namespace pb4u {
namespace {

TEST(SignedDistance, TetrahedronFacesEdgesAndCorners) {
  const TriMesh t = test::corner_tetrahedron();
  struct Case {
    Eigen::Vector3d p;
    double d;  // closed form
  };
  const double s3 = std::sqrt(3.0);
  const std::vector<Case> cases = {
      {{0.1, 0.1, 0.1}, -0.1},                     // inside, nearest the three axis faces
      {{0.2, 0.3, 0.1}, -0.1},                     // inside, nearest z = 0
      {{0.5, 0.5, 0.5}, (1.5 - 1) / s3},           // outside the slanted face, over its interior
      {{0.3, 0.3, -0.2}, 0.2},                     // below z = 0, over its interior
      {{-0.1, -0.1, 0.5}, std::sqrt(0.02)},        // outside the z-axis edge
      {{-0.1, -0.1, -0.1}, std::sqrt(0.03)},       // outside the origin corner
      {{1.2, -0.1, -0.1}, std::sqrt(0.06)},        // outside corner e_x
      {{0.1, 0.1, 0.75}, -(1 - 0.95) / s3},        // inside near corner e_z: the slanted face is nearest
  };
  Eigen::MatrixXd P(cases.size(), 3);
  for (size_t i = 0; i < cases.size(); ++i) P.row(i) = cases[i].p.transpose();
  const Eigen::VectorXd d = signed_distance_to_surface(P, t.V, t.F);
  for (size_t i = 0; i < cases.size(); ++i) EXPECT_NEAR(d(i), cases[i].d, 1e-12) << "case " << i;
}

TEST(SignedDistance, TriangleFeatureOfTheClosestPoint) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_EQ(closest_point_on_triangle({0.2, 0.2, 1}, a, b, c).feature, TriangleFeature::interior);
  EXPECT_EQ(closest_point_on_triangle({0.5, -1, 0}, a, b, c).feature, TriangleFeature::edge_ab);
  EXPECT_EQ(closest_point_on_triangle({1, 1, 0}, a, b, c).feature, TriangleFeature::edge_bc);
  EXPECT_EQ(closest_point_on_triangle({-1, 0.5, 0}, a, b, c).feature, TriangleFeature::edge_ca);
  EXPECT_EQ(closest_point_on_triangle({-1, -1, 0}, a, b, c).feature, TriangleFeature::corner_a);
  EXPECT_EQ(closest_point_on_triangle({2, -0.5, 0}, a, b, c).feature, TriangleFeature::corner_b);
  EXPECT_EQ(closest_point_on_triangle({-0.5, 2, 0}, a, b, c).feature, TriangleFeature::corner_c);
  EXPECT_TRUE(closest_point_on_triangle({0.2, 0.2, 1}, a, b, c).point.isApprox(Eigen::Vector3d(0.2, 0.2, 0)));
}

// Points at radius r in random directions around the sphere's centre.
Eigen::MatrixXd points_at_radii(const std::vector<double>& radii, const Eigen::RowVector3d& centre, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0, 1);
  Eigen::MatrixXd P(radii.size(), 3);
  for (size_t i = 0; i < radii.size(); ++i) {
    Eigen::RowVector3d u(n(rng), n(rng), n(rng));
    P.row(i) = centre + radii[i] * u.normalized();
  }
  return P;
}

TEST(SignedDistance, SphereIsRMinusRAndMatchesBruteForce) {
  const double R = 0.3;
  const Eigen::RowVector3d centre(0.1, 1.2, -0.2);
  const TriMesh sphere = test::icosphere(R, 4, centre);  // 5120 faces
  std::vector<double> radii;
  for (int k = 0; k < 60; ++k) radii.push_back(R * (0.05 + 0.03 * k));  // 0.05 R .. 1.82 R
  const Eigen::MatrixXd P = points_at_radii(radii, centre, 7);
  const Eigen::VectorXd d = signed_distance_to_surface(P, sphere.V, sphere.F);
  for (size_t i = 0; i < radii.size(); ++i) {
    // Subdivided 4 times, faces span ~0.04 rad: the tessellation is within R (1 - cos 0.04)
    // ~ 0.1% of R of the sphere.
    EXPECT_NEAR(d(i), radii[i] - R, 0.01 * R) << "r = " << radii[i];
    if (std::abs(radii[i] - R) > 0.01 * R) EXPECT_EQ(d(i) < 0, radii[i] < R) << "r = " << radii[i];
    // Exactly the tessellated distance: the nearest of every face.
    double best = INFINITY;
    for (int f = 0; f < sphere.F.rows(); ++f)
      best = std::min(best, (P.row(i).transpose() - closest_point_on_triangle(P.row(i).transpose(),
                                                                             sphere.V.row(sphere.F(f, 0)),
                                                                             sphere.V.row(sphere.F(f, 1)),
                                                                             sphere.V.row(sphere.F(f, 2)))
                                                        .point)
                                .norm());
    EXPECT_NEAR(std::abs(d(i)), best, 1e-12) << "r = " << radii[i];
  }
}

// A surface prepared once answers every later query exactly as a one-off query does.
TEST(SignedDistance, APreparedSurfaceAnswersAsTheOneOffQuery) {
  const TriMesh sphere = test::icosphere(0.3, 3, Eigen::RowVector3d(0.1, 1.2, -0.2));
  const SurfaceQuery prepared(sphere.V, sphere.F);
  for (int seed : {7, 8}) {
    std::vector<double> radii;
    for (int k = 0; k < 30; ++k) radii.push_back(0.3 * (0.1 + 0.06 * k));
    const Eigen::MatrixXd P = points_at_radii(radii, Eigen::RowVector3d(0.1, 1.2, -0.2), seed);
    const SurfaceProjection a = prepared.project(P), b = project_onto_surface(P, sphere.V, sphere.F);
    EXPECT_EQ(a.distance, b.distance) << "seed " << seed;
    EXPECT_EQ(a.closest, b.closest) << "seed " << seed;
    EXPECT_EQ(a.outward, b.outward) << "seed " << seed;
  }
  EXPECT_THROW(prepared.project(Eigen::MatrixXd::Constant(1, 3, NAN)), Error);
}

TEST(Penetration, SphereFractionAndDeepestPoint) {
  const double R = 0.3;
  const Eigen::RowVector3d centre(0, 1, 0);
  const TriMesh sphere = test::icosphere(R, 4, centre);
  // 100 garment vertices: 25 at 0.9 R and 5 at 0.5 R inside; 60 at 1.1 R and 10 at 5 R
  // (outside the bounding box) outside.
  std::vector<double> radii;
  for (int k = 0; k < 25; ++k) radii.push_back(0.9 * R);
  for (int k = 0; k < 5; ++k) radii.push_back(0.5 * R);
  for (int k = 0; k < 60; ++k) radii.push_back(1.1 * R);
  for (int k = 0; k < 10; ++k) radii.push_back(5 * R);
  const Eigen::MatrixXd x = points_at_radii(radii, centre, 11);
  const PenetrationFigures p = garment_penetration(x, sphere.V, sphere.F);
  EXPECT_DOUBLE_EQ(p.penetrating_fraction, 0.30);
  EXPECT_NEAR(p.max_penetration_mm, 0.5 * R * 1e3, 0.01 * R * 1e3);

  const PenetrationFigures none = garment_penetration(points_at_radii({1.05 * R, 2 * R}, centre, 3), sphere.V, sphere.F);
  EXPECT_EQ(none.penetrating_fraction, 0.0);
  EXPECT_EQ(none.max_penetration_mm, 0.0);
}

// A body that crosses itself (an upper arm sunk into a torso): a point inside the first box,
// outside the second, whose nearest face is the second box's side inside the first. That
// face's side says "outside"; the point is inside the body, as deep as its distance to the
// faces no part covers. Faces are covered or not whole, so the depth is exact to a face's size
// where parts cross.
TEST(Penetration, APointInsideOnePartNearAnotherPartsCoveredFaceIsInside) {
  const TriMesh body = test::joined(test::box_mesh({0, 0, 0}, {1, 1, 1}), test::box_mesh({0.8, 0.2, 0.2}, {1.8, 0.8, 0.8}));
  const Eigen::MatrixXd p = (Eigen::MatrixXd(1, 3) << 0.75, 0.5, 0.5).finished();
  EXPECT_GT(signed_distance_to_surface(p, body.V, body.F)(0), 0);  // the nearest face's side
  const PenetrationFigures figures = garment_penetration(p, body.V, body.F);
  EXPECT_EQ(figures.penetrating_fraction, 1.0);
  // The nearest outer face: a triangle of the second box's y = 0.2 side (its centroid is outside
  // the first box), at (0.8, 0.2, 0.5); the first box's sides are 0.5 m away.
  EXPECT_NEAR(figures.max_penetration_mm, 1e3 * std::hypot(0.05, 0.3), 1e-9);
  // The body crosses itself: the second box's x = 0.8 side (2 triangles) lies inside the first
  // box, and the first box's x = 1 side (2 triangles, centroids at y, z = 1/3 and 2/3) inside the
  // second; every other face is outside the other box. A closed sphere does not cross itself.
  EXPECT_EQ(figures.body_self_crossing_faces, 4);
  const TriMesh sphere = test::icosphere(0.5, 3, Eigen::RowVector3d(0.5, 0.5, 0.5));
  EXPECT_EQ(garment_penetration(p, sphere.V, sphere.F).body_self_crossing_faces, 0);
}

TEST(Penetration, SummariesOverFramesAndSequences) {
  const PenetrationSummary a = summarize_penetration(std::vector<PenetrationFigures>{{0.1, 2.0}, {0.3, 5.0}, {0.2, 1.0}});
  EXPECT_NEAR(a.penetrating_fraction, 0.2, 1e-15);
  EXPECT_EQ(a.max_penetrating_fraction, 0.3);
  EXPECT_EQ(a.max_penetration_mm, 5.0);
  const PenetrationSummary b = summarize_penetration(std::vector<PenetrationFigures>{{0.0, 0.0}});
  const PenetrationSummary both = summarize_penetration(std::vector<PenetrationSummary>{a, b});
  EXPECT_NEAR(both.penetrating_fraction, 0.1, 1e-15);
  EXPECT_EQ(both.max_penetrating_fraction, 0.3);
  EXPECT_EQ(both.max_penetration_mm, 5.0);
  // Edges through the body: the most on a frame and the frames with any, over frames and sequences.
  PenetrationFigures crossed{0.0, 0.0}, clear{0.0, 0.0};
  crossed.edges_through = 4;
  clear.edges_through = 0;
  const PenetrationSummary c = summarize_penetration(std::vector<PenetrationFigures>{clear, crossed, crossed});
  EXPECT_EQ(c.max_edges_through, 4);
  EXPECT_EQ(c.frames_with_edges_through, 2);
  EXPECT_EQ(c.frames, 3);
  const PenetrationSummary d = summarize_penetration(std::vector<PenetrationSummary>{c, a});
  EXPECT_EQ(d.max_edges_through, 4);
  EXPECT_EQ(d.frames_with_edges_through, 2);
  EXPECT_EQ(d.frames, 6);
  // Frames where the body crosses itself: the most faces on one, and how many frames.
  PenetrationFigures crossing{0.0, 0.0};
  crossing.body_self_crossing_faces = 7;
  const PenetrationSummary e = summarize_penetration(std::vector<PenetrationFigures>{clear, crossing, crossed});
  EXPECT_EQ(e.max_body_self_crossing_faces, 7);
  EXPECT_EQ(e.frames_with_body_self_crossing, 1);
  const PenetrationSummary f = summarize_penetration(std::vector<PenetrationSummary>{e, e, a});
  EXPECT_EQ(f.max_body_self_crossing_faces, 7);
  EXPECT_EQ(f.frames_with_body_self_crossing, 2);
  EXPECT_THROW(summarize_penetration(std::vector<PenetrationFigures>{}), Error);
}

TEST(Penetration, BadInputIsAnError) {
  const TriMesh t = test::corner_tetrahedron();
  Eigen::MatrixXd x = Eigen::MatrixXd::Constant(2, 3, 0.1);
  x(1, 2) = NAN;
  EXPECT_THROW(garment_penetration(x, t.V, t.F), Error);
  EXPECT_THROW(garment_penetration(Eigen::MatrixXd(0, 3), t.V, t.F), Error);
  Eigen::MatrixXi bad = t.F;
  bad(0, 0) = 9;
  EXPECT_THROW(signed_distance_to_surface(Eigen::MatrixXd::Zero(1, 3), t.V, bad), Error);
  Eigen::MatrixXd flat = t.V;
  flat.col(2).setZero();  // every face of zero area, or in one plane
  flat.row(3) << 0.5, 0.5, 0;
  flat.row(1) = flat.row(0);
  flat.row(2) = flat.row(0);
  EXPECT_THROW(signed_distance_to_surface(Eigen::MatrixXd::Zero(1, 3), flat, t.F), Error);
}

TEST(Penetration, TheRolloutCountsClothEdgesThroughTheBodyWithBothEndsOutside) {
  // A triangle whose bottom edge runs straight through a 2 cm sphere, its three corners outside:
  // no vertex is inside, one edge is through, on every frame of a rollout that holds it still.
  const TriMesh sphere = test::icosphere(0.02, 2, Eigen::RowVector3d::Zero());
  RolloutInput in;
  in.garment_rest.V.resize(3, 3);
  in.garment_rest.V << -0.05, 0, 0, 0.05, 0, 0, 0, 0.1, 0;
  in.garment_rest.F.resize(1, 3);
  in.garment_rest.F << 0, 1, 2;
  in.x0 = in.x_prev = in.garment_rest.V;
  in.steps = 2;
  in.body.assign(in.steps + 1, sphere.V);
  in.body_faces = sphere.F;
  in.measure_residual = false;
  const StepFunction hold = [](const FrameState& s, const ClothGeometry&, const TermList&, const BodyContact*) {
    return s.x.to(torch::kFloat64);
  };
  const RolloutResult r = run_rollout(in, hold, PhysicsConfig{});
  ASSERT_EQ(r.penetration.size(), 2u);
  for (const PenetrationFigures& f : r.penetration) {
    EXPECT_EQ(f.penetrating_fraction, 0);
    EXPECT_EQ(f.edges_through, 1);
  }
  const PenetrationSummary s = summarize_penetration(r.penetration);
  EXPECT_EQ(s.max_edges_through, 1);
  EXPECT_EQ(s.frames_with_edges_through, 2);
}

}  // namespace
}  // namespace pb4u
