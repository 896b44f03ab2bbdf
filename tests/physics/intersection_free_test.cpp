// Intersection-free contact (the reference solver with solver.contact = barrier): the broad
// phase misses no pair brute force finds, the barrier potential's gradient, a penetrating frame
// made free before the step, and every frame checked free of the body (no vertex inside, no
// cloth edge through a body triangle) on a cloth dropped on a sphere and on a sphere rising
// fast through a cloth.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "pb4u/mesh/edges.h"
#include "pb4u/physics/barrier_potential.h"
#include "pb4u/physics/body_offset.h"
#include "pb4u/physics/carried_by_body.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/incremental_potential_solve.h"
#include "pb4u/physics/intersection_free_start.h"
#include "pb4u/physics/primitive_distance.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/physics/step_residual.h"
#include "pb4u/rollout/refined_step.h"
#include "pb4u/rollout/rollout.h"
#include "pb4u/spatial/signed_distance_to_surface.h"
#include "pb4u/util/eigen_tensor.h"
#include "pb4u/util/error.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

using V3 = Eigen::Vector3d;

V3 row(const Eigen::MatrixXd& M, int i) { return M.row(i).transpose(); }

// The cloth's smallest signed distance to the body and its edges through the body.
struct Freedom {
  double min_distance;
  int edges_through;
};
Freedom freedom(const Eigen::MatrixXd& x, const Eigen::MatrixXi& edges, const Eigen::MatrixXd& body_V,
                const Eigen::MatrixXi& body_F) {
  return {signed_distance_to_surface(x, body_V, body_F).minCoeff(),
          int(cloth_edges_through_body(x, edges, make_contact_surface(body_V, body_F)).size())};
}

TEST(ContactCandidates, FindEveryPairBruteForceFinds) {
  const TriMesh sphere = test::icosphere(0.25, 2, Eigen::RowVector3d::Zero());
  const ContactSurface body = make_contact_surface(sphere.V, sphere.F);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3), small(-0.02, 0.02);
  const int n = 60;
  Eigen::MatrixXd x(n, 3), dx(n, 3), body_motion(body.V.rows(), 3);
  for (int i = 0; i < n; ++i) {
    x.row(i) << u(rng), u(rng), u(rng);
    dx.row(i) << small(rng), small(rng), small(rng);
  }
  for (int j = 0; j < body.V.rows(); ++j) body_motion.row(j) << small(rng), small(rng), small(rng);
  Eigen::MatrixXi edges(n - 1, 2);
  for (int i = 0; i + 1 < n; ++i) edges.row(i) << i, i + 1;
  const double reach = 0.01;
  const ContactCandidates c = contact_candidates(x, dx, edges, body, body_motion, reach);
  auto has = [](const std::vector<std::array<int, 2>>& pairs, int a, int b) {
    return std::find(pairs.begin(), pairs.end(), std::array<int, 2>{a, b}) != pairs.end();
  };
  int near_pairs = 0;
  for (const double s : {0.0, 0.5, 1.0}) {
    const Eigen::MatrixXd xs = x + s * dx, bs = body.V + s * body_motion;
    for (int i = 0; i < n; ++i)
      for (int f = 0; f < body.F.rows(); ++f)
        if (point_triangle_distance(row(xs, i), row(bs, body.F(f, 0)), row(bs, body.F(f, 1)), row(bs, body.F(f, 2)))
                .distance < reach) {
          ++near_pairs;
          EXPECT_TRUE(has(c.vertex_face, i, f)) << "vertex " << i << " face " << f << " at s " << s;
        }
    for (int e = 0; e < edges.rows(); ++e)
      for (int be = 0; be < body.E.rows(); ++be)
        if (edge_edge_distance(row(xs, edges(e, 0)), row(xs, edges(e, 1)), row(bs, body.E(be, 0)),
                               row(bs, body.E(be, 1)))
                .distance < reach) {
          ++near_pairs;
          EXPECT_TRUE(has(c.edge_edge, e, be)) << "edge " << e << " body edge " << be << " at s " << s;
        }
  }
  EXPECT_GT(near_pairs, 10);  // the sample must hold near pairs for the check to mean anything
}

TEST(BarrierPotential, GradientMatchesFiniteDifferences) {
  // A small cloth 0.3-1.5 mm over a sphere: inside d_hat = 2 mm, every pair active.
  const TriMesh sphere = test::icosphere(0.25, 3, Eigen::RowVector3d::Zero());
  const ContactSurface body = make_contact_surface(sphere.V, sphere.F);
  TriMesh cloth = test::grid_mesh(2, 0.01);
  cloth.V.col(0).array() -= 0.005;
  cloth.V.col(2).array() -= 0.005;
  for (int i = 0; i < cloth.V.rows(); ++i) cloth.V(i, 1) = 0.25 + 3e-4 + 1.2e-3 * (i % 3) / 2.0;
  const Eigen::MatrixXi edges = unique_edges(cloth.F);
  const BarrierSettings settings{2e-3, 10};
  const ContactCandidates c = contact_candidates(cloth.V, {}, edges, body, {}, settings.d_hat);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(cloth.V.rows(), 3);
  const BarrierValue b = barrier_potential(cloth.V, edges, body, c, settings, &G);
  ASSERT_GT(b.active, 0);
  EXPECT_GT(b.energy, 0);
  for (int i = 0; i < cloth.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-8;
      Eigen::MatrixXd plus = cloth.V, minus = cloth.V;
      plus(i, k) += h;
      minus(i, k) -= h;
      const double numeric = (barrier_potential(plus, edges, body, c, settings).energy -
                              barrier_potential(minus, edges, body, c, settings).energy) /
                             (2 * h);
      EXPECT_NEAR(G(i, k), numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << "vertex " << i << " axis " << k;
    }
}

TEST(IntersectionFreeStart, APenetratingFrameIsMadeFreeFirst) {
  // A cloth cutting through a sphere, as an LBS frame can: its middle row inside.
  const TriMesh sphere = test::icosphere(0.25, 3, Eigen::RowVector3d::Zero());
  TriMesh cloth = test::grid_mesh(8, 0.4);
  cloth.V.col(0).array() -= 0.2;
  cloth.V.col(2).array() -= 0.2;
  cloth.V.col(1).array() += 0.2;  // the plane y = 0.2 cuts the sphere of radius 0.25
  const Eigen::MatrixXi edges = unique_edges(cloth.F);
  const Freedom before = freedom(cloth.V, edges, sphere.V, sphere.F);
  ASSERT_LT(before.min_distance, 0);
  const FeasibleStart s = intersection_free_start(cloth.V, cloth.V, edges, sphere.V, sphere.F, 1e-3);
  EXPECT_GT(s.pushed_out, 0);
  EXPECT_EQ(s.excluded_count, 0);
  const Freedom after = freedom(s.x, edges, sphere.V, sphere.F);
  EXPECT_GT(after.min_distance, 0);
  EXPECT_EQ(after.edges_through, 0);
}

// A flat body: one square (two triangles) in the plane y = 0, facing up, 1 m wide.
ContactSurface floor_square() {
  Eigen::MatrixXd V(4, 3);
  V << -0.5, 0, -0.5, 0.5, 0, -0.5, 0.5, 0, 0.5, -0.5, 0, 0.5;
  Eigen::MatrixXi F(2, 3);
  F << 0, 2, 1, 0, 3, 2;
  return make_contact_surface(V, F);
}

TEST(CarriedByBody, ClothOnARisingFloorRidesItAndClothFartherUpIsPushedToTheKeepDistance) {
  // The floor rises 1 cm. Vertex 0 lies 0.2 mm over it (nearer than keep = 0.5 mm): it rides
  // all 1 cm (with the `ride` rule it also rises back to keep over it). Vertex 1 is 5 mm up: the motion closes 10 - 4.5 mm past keep, so it moves 5.5 mm.
  // Vertex 2 is 3 cm up: never reached. Vertex 3 is beside the floor, level with it: the floor
  // slides past it (no approach along their normal): not moved.
  const ContactSurface floor = floor_square();
  Eigen::MatrixXd x(4, 3);
  x << 0, 2e-4, 0, 0.1, 5e-3, 0.1, -0.1, 3e-2, 0, 0.9, 0, 0;
  Eigen::MatrixXd up = Eigen::MatrixXd::Zero(4, 3);
  up.col(1).setConstant(1e-2);
  const Eigen::MatrixXd moved = carried_by_body(x, Eigen::MatrixXi(0, 2), floor, up, {}, 5e-4);
  EXPECT_NEAR(moved(0, 1), 1e-2, 1e-12);
  EXPECT_NEAR(moved(1, 1), 5.5e-3, 1e-12);
  EXPECT_EQ(moved.row(2).norm(), 0);
  EXPECT_EQ(moved.row(3).norm(), 0);
  EXPECT_NEAR(moved.col(0).norm() + moved.col(2).norm(), 0, 1e-15);  // straight up
  // Falling away from the cloth drags nothing; an excluded vertex is left where it is.
  EXPECT_EQ(carried_by_body(x, Eigen::MatrixXi(0, 2), floor, -up, {}, 5e-4).norm(), 0);
  EXPECT_EQ(carried_by_body(x, Eigen::MatrixXi(0, 2), floor, up, {1, 0, 0, 0}, 5e-4).row(0).norm(), 0);
  const Eigen::MatrixXd ridden = carried_by_body(x, Eigen::MatrixXi(0, 2), floor, up, {}, 5e-4, true);
  EXPECT_NEAR(ridden(0, 1), 1e-2 + 5e-4 - 2e-4, 1e-12);
  EXPECT_NEAR(ridden(1, 1), 5.5e-3, 1e-12);
  EXPECT_EQ(ridden.row(3).norm(), 0);
}

// The motion of points p (rows) under a rotation R about the origin.
Eigen::MatrixXd rotation_motion(const Eigen::MatrixXd& p, const Eigen::Matrix3d& R) {
  return (p * R.transpose()) - p;
}

TEST(CarriedByBody, ClothRestingOnAFloorThatTurnsUnderItRidesWithIt) {
  // `ride`: the floor turns 0.1 rad about its normal: no point of it comes closer to the cloth, to
  // first order or at all, but cloth that rode it must not be left behind (a limb turning
  // under a sleeve). Each vertex 0.2 mm over it moves as the floor does under it, and rises to
  // keep (0.5 mm).
  const ContactSurface floor = floor_square();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.1, V3::UnitY()).toRotationMatrix();
  Eigen::MatrixXd x(2, 3);
  x << 0.2, 2e-4, 0.1, -0.3, 2e-4, -0.2;
  const Eigen::MatrixXd moved =
      carried_by_body(x, Eigen::MatrixXi(0, 2), floor, rotation_motion(floor.V, R), {}, 5e-4, true);
  Eigen::MatrixXd foot = x;
  foot.col(1).setZero();
  const Eigen::MatrixXd expected = rotation_motion(foot, R);
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(moved(i, 0), expected(i, 0), 1e-12);
    EXPECT_NEAR(moved(i, 2), expected(i, 2), 1e-12);
    EXPECT_NEAR(moved(i, 1), 5e-4 - 2e-4, 1e-12);
  }
}

TEST(CarriedByBody, RidingAVertexPushedByTwoSurfacesTakesBothPushes) {
  // `ride`: a floor (y = 0) rising 1 cm and a wall (x = 0) moving 1 cm in +x, a vertex in their corner
  // 0.2 mm from each: it must clear both, not only the one with the larger push.
  Eigen::MatrixXd V(8, 3);
  V << 0, 0, -0.25, 0.5, 0, -0.25, 0.5, 0, 0.25, 0, 0, 0.25,  // floor
      0, 0, -0.25, 0, 0.5, -0.25, 0, 0.5, 0.25, 0, 0, 0.25;     // wall
  Eigen::MatrixXi F(4, 3);
  F << 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7;
  const ContactSurface corner = make_contact_surface(V, F);
  Eigen::MatrixXd motion = Eigen::MatrixXd::Zero(8, 3);
  motion.block(0, 1, 4, 1).setConstant(1e-2);
  motion.block(4, 0, 4, 1).setConstant(1e-2);
  Eigen::MatrixXd x(1, 3);
  x << 2e-4, 2e-4, 0;
  const Eigen::MatrixXd moved = carried_by_body(x, Eigen::MatrixXi(0, 2), corner, motion, {}, 5e-4, true);
  // `push` takes one of the two pushes (the larger; here they are equal).
  const Eigen::MatrixXd pushed = carried_by_body(x, Eigen::MatrixXi(0, 2), corner, motion, {}, 5e-4);
  EXPECT_NEAR(pushed.row(0).norm(), 1e-2, 1e-12);
  EXPECT_NEAR(moved(0, 0), 1e-2 + 3e-4, 1e-12);
  EXPECT_NEAR(moved(0, 1), 1e-2 + 3e-4, 1e-12);
  EXPECT_NEAR(moved(0, 2), 0, 1e-12);
}

TEST(CarriedByBody, RidingAClothEdgeAcrossATiltingBodyEdgeTiltsWithIt) {
  // `ride`: a tent's ridge (the z axis) tilts 0.2 rad about the x axis, which it crosses under a long
  // cloth edge 0.2 mm above it. The edge's ends stand 5 cm off the tent: only the edge-edge
  // pair carries them. The ridge's nearest point does not move, so carrying both ends with it
  // would leave the edge where it is while the tilted ridge closes in at second order; each
  // end moves with the ridge where it projects onto it, and the pair ends at keep (0.5 mm).
  Eigen::MatrixXd V(4, 3);
  V << 0, 0, -0.2, 0, 0, 0.2, 0.05, -0.2, 0, -0.05, -0.2, 0;
  Eigen::MatrixXi F(2, 3);
  F << 0, 1, 2, 1, 0, 3;
  const ContactSurface tent = make_contact_surface(V, F);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2, V3::UnitX()).toRotationMatrix();
  const Eigen::MatrixXd motion = rotation_motion(V, R);
  Eigen::MatrixXd x(2, 3);
  x << -0.05, 2e-4, -0.05, 0.05, 2e-4, 0.05;
  Eigen::MatrixXi edge(1, 2);
  edge << 0, 1;
  const Eigen::MatrixXd moved = carried_by_body(x, edge, tent, motion, {}, 5e-4, true);
  EXPECT_EQ(carried_by_body(x, edge, tent, motion, {}, 5e-4).norm(), 0);  // `push`: left where it is
  const Eigen::MatrixXd x_after = x + moved, ridge_after = V.topRows(2) * R.transpose();
  // Still: the tilted ridge is nearer than before.
  EXPECT_LT(edge_edge_distance(row(x, 0), row(x, 1), row(ridge_after, 0), row(ridge_after, 1)).distance, 2e-4);
  EXPECT_NEAR(edge_edge_distance(row(x_after, 0), row(x_after, 1), row(ridge_after, 0), row(ridge_after, 1)).distance,
              5e-4, 2e-5);
  EXPECT_GT(moved(0, 1), 0.05 * std::sin(0.2) * 0.9);  // the end over the rising half goes up
  EXPECT_LT(moved(1, 1), 0);                            // the other goes down with the ridge
}

TEST(IntersectionFreeStart, VerticesNotFreeAreThoseInsideThroughOrTouching) {
  const TriMesh sphere = test::icosphere(0.25, 3, Eigen::RowVector3d::Zero());
  const double d_hat = 1e-3;
  // 0: inside; 1 - 2: outside, but their edge is a chord through the sphere; 3 - 4: an edge
  // 1e-6 m (under a hundredth of d_hat) over the pole; 5 - 6: well clear.
  Eigen::MatrixXd x(7, 3);
  x << 0, 0.2, 0,  //
      -0.3, 0.1, 0, 0.3, 0.1, 0,  //
      -0.1, 0, 0, 0.1, 0, 0,  //
      0, 0.5, 0, 0.1, 0.5, 0;
  const double pole = sphere.V.col(1).maxCoeff();
  x.row(3) << -0.01, pole + 1e-6, 0;
  x.row(4) << 0.01, pole + 1e-6, 0;
  Eigen::MatrixXi edges(3, 2);
  edges << 1, 2, 3, 4, 5, 6;
  const std::vector<char> caught = vertices_not_free_of(x, edges, sphere.V, sphere.F, d_hat);
  EXPECT_EQ(caught, (std::vector<char>{1, 1, 1, 1, 1, 0, 0}));
}

TEST(IntersectionFreeStart, PinnedVerticesGoOutUntilNoEdgeBetweenThemCutsTheBody) {
  // A hexagon of pins 4 mm outside a sphere's equator, joined to a free centre vertex: each
  // chord's middle lies at 0.124 cos 30 = 0.107 m from the centre, 13 mm inside the sphere.
  const double radius = 0.12, ring = radius + 0.004;
  const TriMesh sphere = test::icosphere(radius, 4, Eigen::RowVector3d::Zero());
  Eigen::MatrixXd x(7, 3);
  x.row(0).setZero();
  for (int k = 0; k < 6; ++k) x.row(k + 1) << ring * std::cos(k * M_PI / 3), 0, ring * std::sin(k * M_PI / 3);
  Eigen::MatrixXi faces(6, 3);
  for (int k = 0; k < 6; ++k) faces.row(k) << 0, 1 + k, 1 + (k + 1) % 6;
  const Eigen::MatrixXi edges = unique_edges(faces);
  const std::vector<int> pinned{1, 2, 3, 4, 5, 6};
  const ContactSurface body = make_contact_surface(sphere.V, sphere.F);
  Eigen::MatrixXi ring_edges(6, 2);
  for (int k = 0; k < 6; ++k) ring_edges.row(k) << 1 + k, 1 + (k + 1) % 6;
  ASSERT_EQ(cloth_edges_through_body(x, ring_edges, body).size(), 6u);

  Eigen::MatrixXd held = x;
  const double step = 1e-3;
  EXPECT_EQ(push_pinned_edges_free_of_body(held, pinned, edges, sphere.V, sphere.F, step), 0);
  EXPECT_TRUE(cloth_edges_through_body(held, ring_edges, body).empty());
  EXPECT_EQ(held.row(0), x.row(0));  // not pinned: untouched (it is inside the sphere)
  // Out along the body's normal (the icosphere's: within a few degrees of radial), as far as the
  // chords need: the icosphere lies inside the sphere, so the true sphere's 0.1386 m is the most
  // needed, and a round further (with the slant) at most.
  for (int i : pinned) {
    const Eigen::RowVector3d moved = held.row(i) - x.row(i);
    EXPECT_GT(moved.dot(x.row(i).normalized()), 0.99 * moved.norm()) << i;
    EXPECT_GT(held.row(i).norm(), ring + 0.005) << i;
    EXPECT_LT(held.row(i).norm(), radius / std::cos(M_PI / 6) + 2 * step) << i;
  }
  // With too few rounds the edges still through are counted, not hidden.
  Eigen::MatrixXd short_of = x;
  EXPECT_EQ(push_pinned_edges_free_of_body(short_of, pinned, edges, sphere.V, sphere.F, step, 2), 6);
}

// One frame of the intersection-free solver; the state moves on.
SolverResult barrier_step(FrameState& state, const ClothGeometry& cloth, const PhysicsConfig& config) {
  const TermList terms = build_terms(state.effects, config);
  SolverResult r = solve_reference_frame(state, cloth, terms, config);
  state.x_prev = state.x;
  state.x = r.x_next;
  return r;
}

PhysicsConfig barrier_config() {
  PhysicsConfig config;
  config.solver.contact = "barrier";
  return config;
}

// One frame of the solver refining x_start (a network's step), started as
// config.solver.given_start says; the state stays.
SolverResult refine_with_solver(const FrameState& state, const ClothGeometry& cloth, const PhysicsConfig& config,
                                const torch::Tensor& x_start) {
  const TermList terms = build_terms(state.effects, config);
  const std::optional<BodyContact> contact = body_contact_for(state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config.solver);
  return solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver,
                              barrier ? &*barrier : nullptr, &x_start);
}

// A 6 x 6 cloth (0.3 m) `gap` m over a still sphere of radius 0.25 m, falling: the scene, its
// cloth's geometry and edges, and the sphere as a mesh.
struct ClothOverSphere {
  static constexpr double radius = 0.25;
  TriMesh garment;
  FrameState state;
  ClothGeometry cloth;
  Eigen::MatrixXi edges;
  TriMesh sphere = test::icosphere(radius, 3, Eigen::RowVector3d::Zero());
  explicit ClothOverSphere(double gap)
      : state(test::cloth_above_sphere(6, 0.3, radius, gap, 3, &garment)),
        cloth(make_cloth_geometry(garment)),
        edges(unique_edges(garment.F)) {}
};

TEST(IntersectionFreeSolver, ClothDroppedOnASphereComesToRestOutsideIt) {
  for (const std::string step : {"quasi_newton", "newton"}) {
    SCOPED_TRACE(step);
    ClothOverSphere scene(0.01);
    const double radius = scene.radius;
    FrameState& state = scene.state;
    const ClothGeometry& cloth = scene.cloth;
    const Eigen::MatrixXi& edges = scene.edges;
    const Eigen::MatrixXd body_V = tensor_to_matrix(state.body.vertices);
    const TriMesh& sphere = scene.sphere;
    PhysicsConfig config = barrier_config();
    config.solver.step = step;
    double kinetic = 0;
    for (int frame = 0; frame < 30; ++frame) {
      const SolverResult r = barrier_step(state, cloth, config);
      const Freedom f = freedom(tensor_to_matrix(state.x), edges, body_V, sphere.F);
      ASSERT_GT(f.min_distance, 0) << "frame " << frame;
      ASSERT_EQ(f.edges_through, 0) << "frame " << frame;
      EXPECT_EQ(r.excluded, 0);
      EXPECT_EQ(r.body_lag, 0);  // the sphere stands still: never placed
      EXPECT_GT(r.min_distance, 0);
      kinetic = 0.5 * (cloth.vertex_masses(state.material.density) * state.velocity().pow(2).sum(1)).sum().item<double>();
    }
    // At rest on top of the sphere, within the barrier's reach of its pole.
    const double centre_y = state.x[24][1].item<double>();
    EXPECT_GT(centre_y, radius * 0.99);  // the icosphere's pole is at the radius
    EXPECT_LT(centre_y, radius + 0.005);
    EXPECT_LT(kinetic, 1e-4);
  }
}

TEST(BodyOffset, MovesOutWhereThereIsRoomAndClosesNoGapBetweenParts) {
  // Two spheres of one body, 4 mm apart, offset by 3 mm: moved out by the full offset away
  // from each other, not at all where they face (a uniform offset would make them cross by 2 mm).
  const double radius = 0.1, gap = 0.004, offset = 0.003;
  const TriMesh body = test::joined(test::icosphere(radius, 3, Eigen::RowVector3d::Zero()),
                                    test::icosphere(radius, 3, Eigen::RowVector3d(2 * radius + gap, 0, 0)));
  const Eigen::MatrixXd moved = offset_where_room(body.V, body.F, offset);
  const Eigen::Index half = body.V.rows() / 2;
  double least_far = 1, most = 0;
  for (Eigen::Index i = 0; i < body.V.rows(); ++i) {
    const double by = (moved.row(i) - body.V.row(i)).norm();
    most = std::max(most, by);
    const double outward_x = i < half ? body.V(i, 0) : 2 * radius + gap - body.V(i, 0);
    if (outward_x < -0.5 * radius) least_far = std::min(least_far, by);  // the far sides
  }
  // The moved surfaces stay apart: every moved vertex of the first sphere outside the second.
  const Eigen::MatrixXd second_V = moved.bottomRows(body.V.rows() - half);
  const Eigen::MatrixXi second_F = (body.F.bottomRows(body.F.rows() / 2).array() - int(half)).matrix();
  const double facing_gap = signed_distance_to_surface(moved.topRows(half), second_V, second_F).minCoeff();
  EXPECT_LE(most, offset + 1e-12);
  EXPECT_GT(least_far, 0.99 * offset);
  EXPECT_GT(facing_gap, 0.9 * gap) << "the offset closed the gap between the parts";
}

TEST(IntersectionFreeSolver, ABarrierOffsetHoldsTheClothThatFarOffTheBody) {
  // The sphere drop with a 3 mm contact offset: every frame the cloth stays at least ~the offset
  // off the real sphere (the offset body's faces are within a few tenths of a percent of it),
  // and it comes to rest on the offset surface, not on the sphere.
  ClothOverSphere scene(0.01);
  PhysicsConfig config = barrier_config();
  const double offset = 3e-3;
  config.solver.barrier_offset = offset;
  const Eigen::MatrixXd body_V = tensor_to_matrix(scene.state.body.vertices);
  for (int frame = 0; frame < 30; ++frame) {
    const SolverResult r = barrier_step(scene.state, scene.cloth, config);
    const Freedom f = freedom(tensor_to_matrix(scene.state.x), scene.edges, body_V, scene.sphere.F);
    ASSERT_GT(f.min_distance, 0.95 * offset) << "frame " << frame;
    EXPECT_EQ(r.excluded, 0) << "frame " << frame;
  }
  const double centre_y = scene.state.x[24][1].item<double>();
  EXPECT_GT(centre_y, scene.radius + 0.95 * offset);
  EXPECT_LT(centre_y, scene.radius + offset + 0.005);  // the bound of the drop without offset, moved out
}

TEST(IntersectionFreeSolver, KeepingThePenaltyRestsTheClothWhereThePenaltySolverDoes) {
  // A fine cloth dropped on a finely tessellated sphere, SPEC 3.3's penalty term kept beside the
  // barrier: every frame free of the sphere, and at rest where the penalty solver rests it, since
  // the penalty holds the cloth (its edges too) farther off than d_hat, where the barrier is idle.
  // The barrier alone rests it within d_hat, where the penalty term (the energy every method is
  // measured on) still charges.
  const double radius = 0.25;
  TriMesh g;
  const FrameState start = test::cloth_above_sphere(12, 0.3, radius, 0.01, 4, &g);
  const ClothGeometry cloth = make_cloth_geometry(g);
  const Eigen::MatrixXi edges = unique_edges(g.F);
  const TriMesh sphere = test::icosphere(radius, 4, Eigen::RowVector3d::Zero());
  PhysicsConfig kept = barrier_config(), alone = barrier_config(), penalty;
  kept.solver.barrier_keeps_penalty = true;
  alone.solver.barrier_keeps_penalty = false;
  penalty.solver.contact = "penalty";
  FrameState a = start, b = start, c = start;
  // The collision term of the frame just solved (it reads only x and the body's pose).
  auto collision = [&](const FrameState& s) {
    const std::optional<BodyContact> contact = body_contact_for(s, penalty);
    return energy_report(build_terms(s.effects, penalty), s.x, s, cloth, &*contact).value("collision");
  };
  SolverResult r;
  for (int frame = 0; frame < 20; ++frame) {
    r = barrier_step(a, cloth, kept);
    barrier_step(b, cloth, penalty);
    barrier_step(c, cloth, alone);
    const Freedom f = freedom(tensor_to_matrix(a.x), edges, sphere.V, sphere.F);
    ASSERT_GT(f.min_distance, 0) << "frame " << frame;
    ASSERT_EQ(f.edges_through, 0) << "frame " << frame;
    EXPECT_EQ(r.excluded, 0) << "frame " << frame;
  }
  const double gap = (a.x - b.x).abs().max().item<double>();
  std::printf("at rest: closest vertex %.3f mm off the sphere (barrier alone %.3f mm), %.2g m from the penalty "
              "solver's cloth; collision term %.3g J (barrier alone %.3g J)\n",
              1e3 * freedom(tensor_to_matrix(a.x), edges, sphere.V, sphere.F).min_distance,
              1e3 * freedom(tensor_to_matrix(c.x), edges, sphere.V, sphere.F).min_distance, gap, collision(a),
              collision(c));
  EXPECT_GT(r.min_distance, kept.solver.barrier_distance);  // held by the penalty, beyond d_hat
  // m: the penalty solver's minimum, up to the flat directions of a draped cloth's minimum
  // (friction and buckling: two converged rollouts stand tens of micrometres apart).
  EXPECT_LT(gap, 2e-4);
  EXPECT_LT(collision(a), 0.1 * collision(c));
}

TEST(IntersectionFreeSolver, NewtonReachesTheQuasiNewtonMinimumInFewerIterations) {
  // The cloth settled on the sphere for 10 frames, then one step both ways at a fixed kappa
  // (the same objective), each allowed 1000 iterations.
  ClothOverSphere scene(0.005);
  PhysicsConfig config = barrier_config();
  config.solver.barrier_stiffness_max = 0;
  config.solver.max_iterations = 1000;
  for (int frame = 0; frame < 10; ++frame) barrier_step(scene.state, scene.cloth, config);
  const TermList terms = build_terms(scene.state.effects, config);
  config.solver.step = "quasi_newton";
  const SolverResult quasi = solve_reference_frame(scene.state, scene.cloth, terms, config);
  config.solver.step = "newton";
  const SolverResult newton = solve_reference_frame(scene.state, scene.cloth, terms, config);
  ASSERT_TRUE(quasi.converged);
  ASSERT_TRUE(newton.converged);
  EXPECT_GT(newton.min_distance, 0);
  EXPECT_LE(newton.energy, quasi.energy + 1e-7 * std::abs(quasi.energy)) << newton.energy - quasi.energy;
  std::printf("quasi-Newton %d iterations, Newton %d, energy gap %.3g J\n", quasi.iterations, newton.iterations,
              newton.energy - quasi.energy);
  EXPECT_LT(newton.iterations, quasi.iterations);
  // The same place to a tenth of d_hat: the minimum is flat along some directions (buckling), so
  // two converged steps can stand tens of micrometres apart at equal energy.
  EXPECT_LT((newton.x_next - quasi.x_next).abs().max().item<double>(), 1e-4);  // m
}

TEST(IntersectionFreeSolver, DecreaseToleranceStopsEarlierWithinItsEnergy) {
  // The same settled step as above, Newton to the step tolerance and then with the decrease rule:
  // fewer iterations, an energy within a few times the tolerance of the tight solve's (half the
  // Newton decrement squared is the quadratic model's gap to its minimum), still free of the body.
  ClothOverSphere scene(0.005);
  PhysicsConfig config = barrier_config();
  config.solver.barrier_stiffness_max = 0;
  config.solver.max_iterations = 1000;
  config.solver.step = "newton";
  for (int frame = 0; frame < 10; ++frame) barrier_step(scene.state, scene.cloth, config);
  const TermList terms = build_terms(scene.state.effects, config);
  const SolverResult tight = solve_reference_frame(scene.state, scene.cloth, terms, config);
  const double tolerance = 1e-7;  // J
  config.solver.decrease_tolerance = tolerance;
  const SolverResult loose = solve_reference_frame(scene.state, scene.cloth, terms, config);
  ASSERT_TRUE(tight.converged);
  ASSERT_TRUE(loose.converged);
  std::printf("Newton: %d iterations to the step tolerance, %d to a %.0e J decrease, energy gap %.3g J\n",
              tight.iterations, loose.iterations, tolerance, loose.energy - tight.energy);
  EXPECT_LT(loose.iterations, tight.iterations);
  EXPECT_LT(loose.energy - tight.energy, 4 * tolerance);
  EXPECT_GT(loose.min_distance, 0);
}

TEST(StepResidual, BarrierContactIsMeasuredAgainstTheIntersectionFreeSolversOwnMinimum) {
  // A cloth resting on a sphere after the intersection-free solver's steps: its contacts sit
  // within d_hat (1 mm), where the penalty term (eps 4 mm) still pushes. Measured with the
  // penalty energy its step reads millimetres from a minimum; with the barrier objective the
  // solver solved, it is at the solver's tolerance. A step lifted 1 mm off the solve is not.
  ClothOverSphere scene(0.01);
  FrameState& state = scene.state;
  PhysicsConfig config = barrier_config();
  config.solver.barrier_keeps_penalty = false;  // the barrier alone: the cloth rests within d_hat
  config.solver.barrier_stiffness_max = 0;  // the residual measures at the configured kappa
  config.solver.max_iterations = 1000;
  const TermList terms = build_terms(state.effects, config);
  for (int frame = 0; frame < 20; ++frame) barrier_step(state, scene.cloth, config);
  const std::optional<BodyContact> contact = body_contact_for(state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, scene.cloth, config.solver);
  ASSERT_TRUE(barrier.has_value());
  const SolverResult r = solve_reference_step(state, scene.cloth, terms, &*contact, config.solver, &*barrier);
  ASSERT_TRUE(r.converged) << r.step_norm;
  ASSERT_EQ(r.excluded, 0);
  const double own = step_residual(r.x_next, state, scene.cloth, terms, &*contact, &*barrier);
  const double penalty = step_residual(r.x_next, state, scene.cloth, terms, &*contact);
  std::printf("residual of the converged barrier step: %.3g mm on its own objective, %.3g mm on the penalty energy\n",
              1e3 * own, 1e3 * penalty);
  EXPECT_LT(own, 1e-5);       // m
  EXPECT_GT(penalty, 1e-4);   // the penalty's eps is not where the barrier rests the cloth
  torch::Tensor lifted = r.x_next.clone();
  lifted.select(1, 1).add_(1e-3);
  EXPECT_GT(step_residual(lifted, state, scene.cloth, terms, &*contact, &*barrier), 1e-4);
  // One vertex 1 mm up, out of the cloth's plane: about its offset or more (the barrier's
  // curvature that held it is gone where it was moved to), where the isotropic metric reads it
  // a tenth as long.
  torch::Tensor wrinkled = r.x_next.clone();
  wrinkled[wrinkled.size(0) / 2][1] += 1e-3;
  const double wrinkle = step_residual(wrinkled, state, scene.cloth, terms, &*contact, &*barrier);
  std::printf("one vertex lifted 1 mm: %.3g mm\n", 1e3 * wrinkle);
  EXPECT_GT(wrinkle, 0.5e-3);
}

TEST(IntersectionFreeSolver, AdaptiveStiffnessHoldsAHeavyClothFartherOffTheBody) {
  // A cloth 100x the default density resting on a sphere. With a soft fixed kappa its contacts
  // sink below a hundredth of d_hat, where the next step's start counts them as touching and
  // leaves them to the penalty term. The adaptive kappa doubles while a pair closes in below
  // barrier_gap x d_hat, holds the cloth farther out and keeps it intersection-free.
  auto rest_on_sphere = [](double stiffness, double stiffness_max, bool check_free) {
    ClothOverSphere scene(0.002);
    scene.state.material.density *= 100;
    PhysicsConfig config = barrier_config();
    // L-BFGS, as the adaptive kappa was built and measured. With Newton steps (the default with
    // barrier contact since pb4u 0.2) kappa does not grow fast enough within a step over
    // Newton's few, long iterations: NewtonCarryingKappa... below.
    config.solver.step = "quasi_newton";
    config.solver.barrier_stiffness = stiffness;
    config.solver.barrier_stiffness_max = stiffness_max;
    const Eigen::MatrixXd body_V = tensor_to_matrix(scene.state.body.vertices);
    SolverResult r;
    int excluded = 0;
    for (int frame = 0; frame < 10; ++frame) {
      r = barrier_step(scene.state, scene.cloth, config);
      excluded += r.excluded;
      if (!check_free) continue;
      const Freedom f = freedom(tensor_to_matrix(scene.state.x), scene.edges, body_V, scene.sphere.F);
      EXPECT_GT(f.min_distance, 0) << "frame " << frame;
      EXPECT_EQ(f.edges_through, 0) << "frame " << frame;
      EXPECT_EQ(r.excluded, 0) << "frame " << frame;
    }
    return std::make_pair(r, excluded);
  };
  const auto [fixed, fixed_excluded] = rest_on_sphere(1, 0, false);
  const auto [adaptive, adaptive_excluded] = rest_on_sphere(1, 1e4, true);
  EXPECT_EQ(fixed.barrier_stiffness, 1);
  EXPECT_GT(fixed_excluded, 0);  // sunk past the start's touching distance
  EXPECT_GT(adaptive.barrier_stiffness, 1);
  EXPECT_LE(adaptive.barrier_stiffness, 1e4);
  EXPECT_EQ(adaptive_excluded, 0);
  EXPECT_GT(adaptive.min_distance, fixed.min_distance);
}

TEST(IntersectionFreeSolver, NewtonCarryingKappaFromStepToStepHoldsAHeavyClothOffTheBody) {
  // The heavy cloth above with Newton steps, rolled out by the reference's stepper. Starting
  // every step at kappa = 1 J/m^2, its pairs sink below d_hat / 100 and the next steps' starts
  // leave vertices out of barrier contact. Carrying kappa from step to step (IPC keeps it),
  // kappa grows over the frames and the cloth stays free of the sphere on every frame.
  auto rest_on_sphere = [](bool carries, bool check_free) {
    ClothOverSphere scene(0.002);
    scene.state.material.density *= 100;
    PhysicsConfig config = barrier_config();
    ASSERT_EQ(config.solver.step, "auto");  // Newton with barrier contact
    config.solver.barrier_stiffness = 1;
    config.solver.barrier_stiffness_max = 1e4;
    config.solver.barrier_stiffness_carries = carries;
    auto log = std::make_shared<ContactStepLog>();
    const StepFunction step = reference_stepper(config.solver, log);
    const Eigen::MatrixXd body_V = tensor_to_matrix(scene.state.body.vertices);
    int excluded = 0;
    for (int frame = 0; frame < 10; ++frame) {
      const TermList terms = build_terms(scene.state.effects, config);
      const std::optional<BodyContact> contact = body_contact_for(scene.state, config);
      const torch::Tensor x_next = step(scene.state, scene.cloth, terms, contact ? &*contact : nullptr);
      scene.state.x_prev = scene.state.x;
      scene.state.x = x_next;
      excluded += log->excluded;
      if (!check_free) continue;
      const Freedom f = freedom(tensor_to_matrix(x_next), scene.edges, body_V, scene.sphere.F);
      EXPECT_GT(f.min_distance, 0) << "frame " << frame;
      EXPECT_EQ(f.edges_through, 0) << "frame " << frame;
      EXPECT_EQ(log->excluded, 0) << "frame " << frame;
    }
    if (carries) {
      EXPECT_GT(log->barrier_stiffness, 64);  // grown over the frames (512 here)
      EXPECT_EQ(excluded, 0);
    } else {
      EXPECT_GT(excluded, 0);  // sunk past the start's touching distance
    }
  };
  rest_on_sphere(false, false);
  rest_on_sphere(true, true);
}

TEST(IntersectionFreeSolver, StiffnessCapBelowTheStartIsRefused) {
  ClothOverSphere scene(0.01);
  PhysicsConfig config = barrier_config();
  config.solver.barrier_stiffness = 100;
  config.solver.barrier_stiffness_max = 10;
  EXPECT_THROW(barrier_step(scene.state, scene.cloth, config), Error);
}

// A 0.5 m cloth (8 x 8 cells) resting 5 mm over a sphere of radius 0.2 m that rises at 3 m/s
// (0.1 m a frame).
struct RisingSphere {
  static constexpr double radius = 0.2, speed = 3;
  TriMesh g;
  FrameState state;
  ClothGeometry cloth;
  Eigen::MatrixXi edges;
  TriMesh sphere;
  RisingSphere()
      : state(test::cloth_above_sphere(8, 0.5, radius, 0.005, 3, &g)),
        cloth(make_cloth_geometry(g)),
        edges(unique_edges(g.F)),
        sphere(test::icosphere(radius, 3, Eigen::RowVector3d::Zero())) {}
  // The sphere's vertices `frames` frames up.
  Eigen::MatrixXd sphere_at(int frames) const {
    Eigen::MatrixXd V = sphere.V;
    V.col(1).array() += speed * state.dt * frames;
    return V;
  }
};

TEST(IntersectionFreeSolver, ASphereRisingFastThroughAClothCarriesItWithoutCrossing) {
  RisingSphere scene;
  FrameState& state = scene.state;
  const ClothGeometry& cloth = scene.cloth;
  const Eigen::MatrixXi& edges = scene.edges;
  const TriMesh& sphere = scene.sphere;
  const double radius = scene.radius, speed = scene.speed;
  const PhysicsConfig config = barrier_config();
  for (int frame = 0; frame < 8; ++frame) {
    const Eigen::MatrixXd at_t = scene.sphere_at(frame), at_next = scene.sphere_at(frame + 1);
    state.body.vertices = test::positions_tensor(at_t);
    state.body.next_vertices = test::positions_tensor(at_next);
    const SolverResult r = barrier_step(state, cloth, config);
    const Freedom f = freedom(tensor_to_matrix(state.x), edges, at_next, sphere.F);
    EXPECT_EQ(r.excluded, 0) << "frame " << frame;
    EXPECT_LT(r.body_lag, 1e-4) << "frame " << frame;  // the cloth lets the sphere through
    ASSERT_GT(f.min_distance, 0) << "frame " << frame;
    ASSERT_EQ(f.edges_through, 0) << "frame " << frame;
  }
  // Carried up: the cloth's centre is over the sphere's top, 0.8 m up by now.
  EXPECT_GT(state.x[40][1].item<double>(), radius + speed * state.dt * 8);
}

TEST(IntersectionFreeSolver, PinsRideWithTheBodyTheyAreHeldTo) {
  // A cloth hangs 5 mm behind a 10 cm thick box, its top row pinned to targets that follow the
  // box at 0.9 m/s (3 cm a frame), as a waistband follows a walking body. Each frame the pins'
  // targets lie 25 mm inside the box where it stands at t: moved with the box, they never cross it.
  const double speed = 0.03;  // m per frame
  TriMesh g = test::grid_mesh(6, 0.3);
  Eigen::MatrixXd V(g.V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) V.row(i) << -0.005, 0.05 + g.V(i, 0), g.V(i, 2) - 0.15;
  g.V = V;
  const ClothGeometry cloth = make_cloth_geometry(g);
  const Eigen::MatrixXi edges = unique_edges(g.F);
  const TriMesh box = test::box_mesh(Eigen::RowVector3d(0, 0, -0.25), Eigen::RowVector3d(0.1, 0.45, 0.25));
  FrameState state = test::resting_state(test::positions_tensor(V));
  state.effects.gravity = state.effects.collision = state.effects.friction = state.effects.pins = true;
  state.body.faces = test::faces_tensor(box.F);
  torch::Tensor pinned = torch::zeros({V.rows()}, torch::kBool);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (V(i, 1) > 0.349) pinned[i] = true;
  state.pinned = pinned;
  const PhysicsConfig config = barrier_config();
  for (int frame = 0; frame < 6; ++frame) {
    Eigen::MatrixXd at_t = box.V, at_next = box.V, targets = V;
    at_t.col(0).array() += speed * frame;
    at_next.col(0).array() += speed * (frame + 1);
    targets.col(0).array() += speed * (frame + 1);
    state.body.vertices = test::positions_tensor(at_t);
    state.body.next_vertices = test::positions_tensor(at_next);
    state.pin_targets = test::positions_tensor(targets);
    const SolverResult r = barrier_step(state, cloth, config);
    EXPECT_EQ(r.excluded, 0) << "frame " << frame;
    EXPECT_EQ(r.caught_by_body, 0) << "frame " << frame;
    EXPECT_LT(r.body_lag, 1e-9) << "frame " << frame;
    const Eigen::MatrixXd x = tensor_to_matrix(state.x);
    for (Eigen::Index i = 0; i < V.rows(); ++i)
      if (pinned[i].item<bool>()) ASSERT_LT((x.row(i) - targets.row(i)).norm(), 1e-12) << "frame " << frame;
    const Freedom f = freedom(x, edges, at_next, box.F);
    ASSERT_GT(f.min_distance, 0) << "frame " << frame;
    ASSERT_EQ(f.edges_through, 0) << "frame " << frame;
  }
}

TEST(IntersectionFreeSolver, PinsTheBodyMovesIntoLeaveContactAndTheBodyGetsToItsPose) {
  // The cloth of the test above hangs 5 mm behind the box, its top row pinned where it is; the
  // box moves 3 cm into it. The pins cannot give way and hold the box's moves back: with
  // solver.release_held_cloth they leave barrier contact (staying on their targets, inside the
  // box) and the box gets to its pose, pushing the free cloth ahead of it.
  TriMesh g = test::grid_mesh(6, 0.3);
  Eigen::MatrixXd V(g.V.rows(), 3);
  for (Eigen::Index i = 0; i < V.rows(); ++i) V.row(i) << -0.005, 0.05 + g.V(i, 0), g.V(i, 2) - 0.15;
  g.V = V;
  const ClothGeometry cloth = make_cloth_geometry(g);
  const TriMesh box = test::box_mesh(Eigen::RowVector3d(0, 0, -0.25), Eigen::RowVector3d(0.1, 0.45, 0.25));
  FrameState state = test::resting_state(test::positions_tensor(V));
  state.effects.gravity = state.effects.collision = state.effects.friction = state.effects.pins = true;
  state.body.faces = test::faces_tensor(box.F);
  torch::Tensor pinned = torch::zeros({V.rows()}, torch::kBool);
  int pins = 0;
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (V(i, 1) > 0.349) pinned[i] = true, ++pins;
  state.pinned = pinned;
  state.pin_targets = test::positions_tensor(V);
  Eigen::MatrixXd at_next = box.V;
  at_next.col(0).array() -= 0.03;
  state.body.vertices = test::positions_tensor(box.V);
  state.body.next_vertices = test::positions_tensor(at_next);
  PhysicsConfig config = barrier_config();
  config.solver.release_held_cloth = true;
  const SolverResult r = barrier_step(state, cloth, config);
  EXPECT_EQ(r.body_lag, 0);
  EXPECT_GE(r.released, 1);
  EXPECT_LE(r.excluded, r.released);  // nothing else left contact
  const Eigen::MatrixXd x = tensor_to_matrix(state.x);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
    if (pinned[i].item<bool>()) ASSERT_LT((x.row(i) - V.row(i)).norm(), 1e-12) << i;
  EXPECT_LT(x.col(0).minCoeff(), -0.03);  // the free cloth went ahead of the box's face
}

TEST(RefinedStep, AnyIterationCountEndsFreeOfTheBodyAndMoreIterationsNeverRaiseThePotential) {
  // A stand-in for the network: the ballistic step pushed 2 cm down, into the sphere the cloth
  // falls on (it starts 5 mm over it).
  const ClothOverSphere scene(0.005);
  const FrameState& state = scene.state;
  const ClothGeometry& cloth = scene.cloth;
  const Eigen::MatrixXi& edges = scene.edges;
  const TriMesh& sphere = scene.sphere;
  const PhysicsConfig config = barrier_config();
  const TermList terms = build_terms(state.effects, config);
  const std::optional<BodyContact> contact = body_contact_for(state, config);
  const StepFunction into_the_body = [](const FrameState& s, const ClothGeometry&, const TermList&,
                                        const BodyContact*) {
    return (2 * s.x - s.x_prev - torch::tensor({0.0, 0.02, 0.0}, torch::kFloat64)).contiguous();
  };
  ASSERT_LT(freedom(tensor_to_matrix(into_the_body(state, cloth, terms, nullptr)), edges, sphere.V, sphere.F)
                .min_distance,
            0);
  // The solver's objective: the terms but the penalty collision, plus the barrier against the body.
  const ContactSurface body = make_contact_surface(sphere.V, sphere.F);
  auto potential = [&](const torch::Tensor& x) {
    double e = 0;
    for (const auto& term : terms)
      if (term->name() != "collision") e += term->energy(x, state, cloth, &*contact).item<double>();
    const Eigen::MatrixXd X = tensor_to_matrix(x);
    BarrierSettings settings;  // the refinement's fixed kappa (refined_step.h)
    settings.d_hat = config.solver.barrier_distance;
    settings.stiffness = config.solver.barrier_stiffness;
    return e + barrier_potential(X, edges, body, contact_candidates(X, {}, edges, body, {}, settings.d_hat), settings)
                   .energy;
  };
  for (const std::string step : {"quasi_newton", "newton"}) {
    SCOPED_TRACE(step);
    double last = std::numeric_limits<double>::infinity();
    for (const int n : {0, 1, 2, 5, 20}) {
      RefineConfig refine;
      refine.iterations = n;
      refine.step = step;
      auto log = std::make_shared<ContactStepLog>();
      const torch::Tensor x = refined_stepper(into_the_body, config.solver, refine, log)(state, cloth, terms, &*contact);
      const Freedom f = freedom(tensor_to_matrix(x), edges, sphere.V, sphere.F);
      EXPECT_GT(f.min_distance, 0) << n << " iterations";
      EXPECT_EQ(f.edges_through, 0) << n << " iterations";
      EXPECT_EQ(log->excluded, 0) << n << " iterations";
      const double p = potential(x);
      EXPECT_LE(p, last + 1e-12 * std::abs(last)) << n << " iterations";
      last = p;
    }
  }
}

TEST(RefinedStep, WithoutContactAStepAboveTheSolversOwnStartIsReplacedByIt) {
  // A cloth falling freely (no body): a "network" that throws one vertex 0.3 m off the
  // ballistic step is far above the solver's own start in its objective; the converged step is
  // below it.
  TriMesh garment;
  FrameState state = test::cloth_above_sphere(6, 0.3, 0.25, 0.005, 2, &garment);
  state.effects.collision = state.effects.friction = false;
  state.body = {};
  const ClothGeometry cloth = make_cloth_geometry(garment, torch::kFloat64);
  const PhysicsConfig config;
  const TermList terms = build_terms(state.effects, config);
  const torch::Tensor ballistic =
      2 * state.x - state.x_prev +
      torch::tensor({state.gravity[0], state.gravity[1], state.gravity[2]}, torch::kFloat64) * (state.dt * state.dt);
  const StepFunction thrown = [](const FrameState& s, const ClothGeometry&, const TermList&, const BodyContact*) {
    torch::Tensor x = (2 * s.x - s.x_prev).clone();
    x[7][1] += 0.3;
    return x;
  };
  const torch::Tensor converged = solve_reference_frame(state, cloth, terms, config).x_next;
  const StepFunction at_the_minimum = [&](const FrameState&, const ClothGeometry&, const TermList&,
                                          const BodyContact*) { return converged; };
  auto potential = [&](const torch::Tensor& x) {
    double e = 0;
    for (const auto& term : terms) e += term->energy(x, state, cloth, nullptr).item<double>();
    return e;
  };
  RefineConfig none;  // no iteration: the start itself comes out
  none.iterations = 0;
  auto log = std::make_shared<ContactStepLog>();
  const torch::Tensor from_thrown = refined_stepper(thrown, config.solver, none, log)(state, cloth, terms, nullptr);
  EXPECT_TRUE(log->own_start);
  EXPECT_LT(potential(from_thrown), potential(thrown(state, cloth, terms, nullptr)));
  // The own start: the ballistic prediction (no pins).
  EXPECT_LT((from_thrown - ballistic).abs().max().item<double>(), 1e-12);
  const torch::Tensor from_minimum = refined_stepper(at_the_minimum, config.solver, none, log)(state, cloth, terms, nullptr);
  EXPECT_FALSE(log->own_start);
  EXPECT_LT((from_minimum - converged).abs().max().item<double>(), 1e-12);
  // With iterations, the refinement from the thrown step reaches the converged step's energy.
  RefineConfig twenty;
  twenty.iterations = 20;
  const torch::Tensor refined = refined_stepper(thrown, config.solver, twenty, log)(state, cloth, terms, nullptr);
  EXPECT_NEAR(potential(refined), potential(converged), 1e-6 * std::abs(potential(converged)) + 1e-9);
}

// A step that does not see the body: the cloth left where it was while a sphere rises 0.1 m
// under it (3 m/s), so that at t + dt the cloth's middle is deep inside the sphere. Swept from
// the cloth at t against the rising sphere (given_start swept), the sphere carries the cloth
// up, none left out and no edge through it. Made free where it stands (at_step) the cloth is
// pushed out of the sphere at its pose, here with nothing left out, so fewer_left_out keeps
// that start (the box at 6 m/s in the hard cases is where it does not: tests/hard).
TEST(RefinedStep, AStepLeftInsideAFastBodyCanStartSweptFromTheClothAtT) {
  RisingSphere s;
  const Eigen::MatrixXd at_next = s.sphere_at(1);
  s.state.body.next_vertices = test::positions_tensor(at_next);
  const torch::Tensor left_behind = s.state.x.clone();
  ASSERT_LT(freedom(tensor_to_matrix(left_behind), s.edges, at_next, s.sphere.F).min_distance, -0.05);
  auto refine = [&](const std::string& given_start) {
    PhysicsConfig config = barrier_config();
    config.solver.given_start = given_start;
    config.solver.max_iterations = 20;
    return refine_with_solver(s.state, s.cloth, config, left_behind);
  };
  for (const std::string given_start : {"swept", "at_step"}) {
    const SolverResult r = refine(given_start);
    EXPECT_EQ(r.swept_start, given_start == "swept") << given_start;
    EXPECT_EQ(r.excluded, 0) << given_start;
    const Freedom f = freedom(tensor_to_matrix(r.x_next), s.edges, at_next, s.sphere.F);
    EXPECT_GT(f.min_distance, 0) << given_start;
    EXPECT_EQ(f.edges_through, 0) << given_start;
    EXPECT_GT(r.x_next[40][1].item<double>(), s.radius + s.speed * s.state.dt) << given_start << ": over the sphere";
  }
  const SolverResult at_step = refine("at_step");
  for (const std::string rule : {"fewer_left_out", "swept_if_left_out"}) {
    const SolverResult r = refine(rule);
    EXPECT_FALSE(r.swept_start) << rule;
    EXPECT_TRUE(torch::equal(r.x_next, at_step.x_next)) << rule;
  }
}

// The sphere rises 0.2 m in the frame, through the cloth left where it was: made free where it
// stands (at_step) the step leaves 7 vertices out of contact and cloth edges through the sphere;
// swept, the sphere carries the cloth up and leaves none out. fewer_left_out_to_tolerance takes
// the step where it stands for a fixed count (a swept start leaves the sphere's whole motion to
// the iterations: on the demo walk one iteration a frame from it diverges, docs/physics.md) and
// sweeps in the solve to the tolerance, which runs even where the count met the tolerance, as
// long as the count left vertices out.
TEST(RefinedStep, FewerLeftOutToToleranceCountsFromTheStepAndSolvesToTheToleranceSwept) {
  RisingSphere s;
  Eigen::MatrixXd at_next = s.sphere.V;
  at_next.col(1).array() += 0.2;
  s.state.body.next_vertices = test::positions_tensor(at_next);
  const torch::Tensor left_behind = s.state.x.clone();
  auto refined = [&](const std::string& given_start, int iterations, double tolerance_mm, ContactStepLog* log) {
    PhysicsConfig config = barrier_config();
    config.solver.given_start = given_start;
    config.solver.own_start_where_left_out = false;  // the rules alone; the own start: the next test
    const TermList terms = build_terms(s.state.effects, config);
    const std::optional<BodyContact> contact = body_contact_for(s.state, config);
    RefineConfig refine;
    refine.iterations = iterations;
    refine.tolerance_mm = tolerance_mm;
    return refine_step(left_behind, s.state, s.cloth, terms, &*contact, config.solver, refine, log);
  };
  ContactStepLog log;
  const torch::Tensor at_step = refined("at_step", 2, 0, &log);
  ASSERT_GT(log.excluded, 0) << "the step cuts the sphere with no free place near";
  ASSERT_GT(freedom(tensor_to_matrix(at_step), s.edges, at_next, s.sphere.F).edges_through, 0);
  const torch::Tensor fewer = refined("fewer_left_out", 2, 0, &log);
  ASSERT_EQ(log.excluded, 0);
  ASSERT_FALSE(torch::equal(fewer, at_step)) << "fewer_left_out sweeps at a fixed count";
  EXPECT_TRUE(torch::equal(refined("fewer_left_out_to_tolerance", 2, 0, &log), at_step));
  EXPECT_GT(log.excluded, 0);
  // 2 iterations at most then to 1 mm, and then to a tolerance the start already meets: at_step
  // stops after its first iteration with the cloth through the sphere, the rule goes on from
  // its own sweep.
  const torch::Tensor one = refined("at_step", 1, 0, &log);
  ASSERT_TRUE(torch::equal(refined("at_step", 2, 1000.0, &log), one));
  ASSERT_GT(freedom(tensor_to_matrix(one), s.edges, at_next, s.sphere.F).edges_through, 0);
  for (const double tolerance_mm : {1.0, 1000.0}) {
    const torch::Tensor x = refined("fewer_left_out_to_tolerance", 2, tolerance_mm, &log);
    EXPECT_EQ(log.excluded, 0) << tolerance_mm << " mm";
    const Freedom f = freedom(tensor_to_matrix(x), s.edges, at_next, s.sphere.F);
    EXPECT_GT(f.min_distance, 0) << tolerance_mm << " mm";
    EXPECT_EQ(f.edges_through, 0) << tolerance_mm << " mm";
  }
}

// own_start_where_left_out: the sphere rises 0.2 m through the step left where it was, which
// made free where it stands leaves vertices out of contact; the solve then starts as the
// solver's own does (the ballistic prediction swept from t), so it ends where the solver's own
// step ends, free of the sphere. Where the step leaves nothing out the switch changes nothing.
TEST(RefinedStep, AStepThatLeavesClothOutStartsAsTheSolversOwnWhereAskedTo) {
  RisingSphere s;
  const torch::Tensor left_behind = s.state.x.clone();
  EXPECT_TRUE(ReferenceSolverConfig().own_start_where_left_out) << "on by default";
  auto solve = [&](const Eigen::MatrixXd& sphere_next, bool own_where_left_out, const torch::Tensor* x_start) {
    s.state.body.next_vertices = test::positions_tensor(sphere_next);
    PhysicsConfig config = barrier_config();
    config.solver.given_start = "at_step";
    config.solver.max_iterations = 10;
    config.solver.own_start_where_left_out = own_where_left_out;
    const TermList terms = build_terms(s.state.effects, config);
    const std::optional<BodyContact> contact = body_contact_for(s.state, config);
    const std::optional<BarrierStepInput> barrier = barrier_step_input(s.state, s.cloth, config.solver);
    return solve_reference_step(s.state, s.cloth, terms, &*contact, config.solver, &*barrier, x_start);
  };
  Eigen::MatrixXd far_up = s.sphere.V;
  far_up.col(1).array() += 0.2;
  const SolverResult at_step = solve(far_up, false, &left_behind);
  ASSERT_GT(at_step.excluded, 0) << "the step cuts the sphere with no free place near";
  ASSERT_FALSE(at_step.own_start);
  const SolverResult own = solve(far_up, true, &left_behind);
  EXPECT_TRUE(own.own_start);
  EXPECT_EQ(own.excluded, 0);
  const Freedom f = freedom(tensor_to_matrix(own.x_next), s.edges, far_up, s.sphere.F);
  EXPECT_GT(f.min_distance, 0);
  EXPECT_EQ(f.edges_through, 0);
  const SolverResult solvers_own = solve(far_up, true, nullptr);
  EXPECT_TRUE(torch::allclose(own.x_next, solvers_own.x_next, 0, 1e-12));
  // A refinement's fixed count under the default rule starts at the step where it stands (a
  // swept start leaves the body's whole motion to a few iterations); under at_step it too starts
  // as the solver's own where the step leaves cloth out.
  auto refined = [&](const std::string& given_start, ContactStepLog* log) {
    PhysicsConfig config = barrier_config();
    config.solver.given_start = given_start;
    config.solver.own_start_where_left_out = true;
    const TermList terms = build_terms(s.state.effects, config);
    const std::optional<BodyContact> contact = body_contact_for(s.state, config);
    RefineConfig refine;
    refine.iterations = 2;
    return refine_step(left_behind, s.state, s.cloth, terms, &*contact, config.solver, refine, log);
  };
  ContactStepLog log;
  refined("fewer_left_out_to_tolerance", &log);
  EXPECT_FALSE(log.own_start) << "a fixed count under the default rule";
  EXPECT_GT(log.excluded, 0);
  refined("at_step", &log);
  EXPECT_TRUE(log.own_start) << "a fixed count under at_step";
  EXPECT_EQ(log.excluded, 0);
  // One frame's rise: the step left where it was is pushed out where it stands, none left out.
  const SolverResult near_off = solve(s.sphere_at(1), false, &left_behind);
  ASSERT_EQ(near_off.excluded, 0);
  const SolverResult near_on = solve(s.sphere_at(1), true, &left_behind);
  EXPECT_FALSE(near_on.own_start);
  EXPECT_TRUE(torch::equal(near_on.x_next, near_off.x_next));
}

// Two spheres (r = 0.1 m) 0.1 m apart close on a 2 cm patch between them and overlap by 0.1 m
// at t + dt: the body crosses itself where the patch is, the patch inside both spheres there.
struct SpheresClosingOnPatch {
  TriMesh patch = test::grid_mesh(3, 0.02);
  ClothGeometry cloth;
  FrameState state;
  TriMesh body;
  Eigen::MatrixXd body_next;
  SpheresClosingOnPatch() {
    patch.V.col(0).array() -= 0.01;
    patch.V.col(2).array() -= 0.01;
    patch.V.col(1).setZero();
    cloth = make_cloth_geometry(patch);
    state = test::resting_state(test::positions_tensor(patch.V));
    state.effects.gravity = state.effects.collision = true;
    const TriMesh left = test::icosphere(0.1, 2, Eigen::RowVector3d(-0.15, 0, 0));
    body = test::joined(left, test::icosphere(0.1, 2, Eigen::RowVector3d(0.15, 0, 0)));
    const Eigen::Index nl = left.V.rows();
    body_next = body.V;
    body_next.topRows(nl).col(0).array() += 0.1;
    body_next.bottomRows(body.V.rows() - nl).col(0).array() -= 0.1;
    state.body.vertices = test::positions_tensor(body.V);
    state.body.next_vertices = test::positions_tensor(body_next);
    state.body.faces = test::faces_tensor(body.F);
  }
};

// A step that did not see the spheres (the patch left where it was) is inside both, with no
// free place near, so made free where it stands (at_step) it leaves vertices out of contact.
// swept_if_left_out then starts as swept does, from the patch at t, and the spheres' moves
// carry it as far as they leave it room.
TEST(RefinedStep, AStepPinchedWhereTheBodyCrossesItselfStartsSweptWhenItLeavesClothOut) {
  const SpheresClosingOnPatch s;
  const torch::Tensor left_behind = s.state.x.clone();
  auto refine = [&](const std::string& given_start) {
    PhysicsConfig config = barrier_config();
    config.solver.given_start = given_start;
    config.solver.own_start_where_left_out = false;  // the rules alone
    config.solver.max_iterations = 10;
    return refine_with_solver(s.state, s.cloth, config, left_behind);
  };
  const SolverResult at_step = refine("at_step");
  ASSERT_FALSE(at_step.swept_start);
  ASSERT_GT(at_step.excluded, 0) << "the pinched patch finds no free place where it stands";
  const SolverResult swept = refine("swept");
  const SolverResult r = refine("swept_if_left_out");
  EXPECT_TRUE(r.swept_start);
  EXPECT_EQ(r.excluded, swept.excluded);
  EXPECT_TRUE(torch::allclose(r.x_next, swept.x_next, 0, 1e-12));
  EXPECT_TRUE(torch::isfinite(r.x_next).all().item<bool>());
}

// The patch between the spheres is nearest, at t, to the inner caps, which at t + dt lie inside
// the other sphere: SPEC 3.3's plane of such a face pushes the cloth along x, through the lens
// where the spheres overlap and deeper into the other one. penalty_faces = outer measures it
// against the faces no other part covers, the nearest of which ring the lens: their planes push
// the cloth out across x, towards the surface of the two spheres together, and each such face's
// outside is outside both spheres. A body that does not cross itself keeps the step's contact.
TEST(RefinedStep, ClothPinchedWhereTheBodyCrossesItselfIsPushedTowardsTheFacesNoOtherPartCovers) {
  const SpheresClosingOnPatch s;
  PhysicsConfig config = barrier_config();
  config.solver.penalty_faces = "outer";
  const std::optional<BodyContact> all = body_contact_for(s.state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(s.state, s.cloth, config.solver);
  const std::optional<BodyContact> outer = barrier->solved_contact(s.state, &*all);
  ASSERT_TRUE(outer);
  const Eigen::MatrixXd all_normal = tensor_to_matrix(all->normal), outer_normal = tensor_to_matrix(outer->normal);
  const Eigen::MatrixXd outer_point = tensor_to_matrix(outer->point);
  const Eigen::RowVector3d left_centre(-0.05, 0, 0), right_centre(0.05, 0, 0);
  for (Eigen::Index i = 0; i < all_normal.rows(); ++i) {
    EXPECT_GT(std::abs(all_normal(i, 0)), 0.9) << "vertex " << i << ": an inner cap's face, facing along x";
    EXPECT_GT(outer_normal.row(i).tail<2>().norm(), std::abs(outer_normal(i, 0))) << "vertex " << i;
    const Eigen::RowVector3d outside = outer_point.row(i) + 1e-4 * outer_normal.row(i);
    EXPECT_GT(std::min((outside - left_centre).norm(), (outside - right_centre).norm()), 0.095) << "vertex " << i;
  }
  EXPECT_TRUE(torch::equal(outer->in_contact, all->in_contact));
  const torch::Tensor kept = torch::tensor(barrier->outer_faces, torch::kInt64);
  EXPECT_TRUE(torch::isin(outer->face, kept).all().item<bool>()) << "faces are rows of the whole body";
  // Solved from the step left where it was, the patch moves out from the axis towards the
  // lens's rim (0.087 m from the axis) and stays within the spheres' reach (with "all", the
  // planes of the covered faces throw it off through the other sphere, 0.47 m on 2026-11-29).
  const torch::Tensor left_behind = s.state.x.clone();
  const torch::Tensor outer_x = refine_with_solver(s.state, s.cloth, config, left_behind).x_next;
  const double start_axis = left_behind.slice(1, 1, 3).norm(2, 1).mean().item<double>();
  EXPECT_GT(outer_x.slice(1, 1, 3).norm(2, 1).mean().item<double>(), start_axis + 0.04);
  EXPECT_LT(outer_x.abs().max().item<double>(), 0.11);
  // Apart, the spheres do not cross themselves: no faces are set aside and the contact stays.
  FrameState apart = s.state;
  apart.body.next_vertices = apart.body.vertices;
  const std::optional<BarrierStepInput> apart_input = barrier_step_input(apart, s.cloth, config.solver);
  EXPECT_TRUE(apart_input->outer_faces.empty());
  EXPECT_FALSE(apart_input->solved_contact(apart, &*all));
}

TEST(RefinedStep, ACountThenAToleranceStopsTheCountAtTheToleranceThenGoesOnToTheMinimum) {
  const ClothOverSphere scene(0.005);
  const PhysicsConfig config = barrier_config();
  const TermList terms = build_terms(scene.state.effects, config);
  const std::optional<BodyContact> contact = body_contact_for(scene.state, config);
  const torch::Tensor into_the_body =
      (2 * scene.state.x - scene.state.x_prev - torch::tensor({0.0, 0.02, 0.0}, torch::kFloat64)).contiguous();
  auto refined = [&](const torch::Tensor& x, int iterations, double tolerance_mm) {
    RefineConfig refine;
    refine.iterations = iterations;
    refine.tolerance_mm = tolerance_mm;
    return refine_step(x, scene.state, scene.cloth, terms, &*contact, config.solver, refine);
  };
  // With a tolerance the count is a most: one its start already meets stops it after its first
  // iteration...
  const torch::Tensor met_at_start = refined(into_the_body, 2, 1000);
  EXPECT_TRUE(torch::equal(met_at_start, refined(into_the_body, 1, 0)));
  EXPECT_FALSE(torch::equal(met_at_start, refined(into_the_body, 2, 0)));
  // ...and one met within the count stops it there, where the solve to the tolerance alone
  // stops; the count run whole goes further.
  const torch::Tensor loose = refined(into_the_body, 0, 0.01);
  EXPECT_TRUE(torch::equal(refined(into_the_body, 50, 0.01), loose));
  EXPECT_GT((refined(into_the_body, 50, 0) - loose).abs().max().item<double>(), 1e-7);
  // A tight one goes on past the count to the minimum: one more iteration barely moves it.
  const torch::Tensor two = refined(into_the_body, 2, 0);
  const torch::Tensor tight = refined(into_the_body, 2, 1e-3);
  const double moved = (tight - two).abs().max().item<double>();
  EXPECT_GT(moved, 1e-5);
  EXPECT_LT((refined(tight, 1, 0) - tight).abs().max().item<double>(), 1e-3 * moved);
}

// Two plates of one body, 1 cm apart, a 10 cm cloth of grid x grid vertices between them; the
// upper plate (half-width `upper` m) comes down 2 cm in the frame, through the lower one.
struct PlatesClosingOnCloth {
  TriMesh g;
  ClothGeometry cloth;
  FrameState state;
  Eigen::MatrixXi body_F = Eigen::MatrixXi(4, 3);
  Eigen::MatrixXd body_next;
  PlatesClosingOnCloth(int grid, double upper) {
    g = test::grid_mesh(grid, 0.1);
    g.V.col(0).array() -= 0.05;
    g.V.col(2).array() -= 0.05;
    g.V.col(1).setConstant(0.005);
    cloth = make_cloth_geometry(g);
    state = test::resting_state(test::positions_tensor(g.V));
    state.effects.gravity = state.effects.collision = true;
    Eigen::MatrixXd body_t(8, 3);
    body_t << -0.5, 0, -0.5, 0.5, 0, -0.5, 0.5, 0, 0.5, -0.5, 0, 0.5,  // lower plate, facing up
        -upper, 0.01, -upper, upper, 0.01, -upper, upper, 0.01, upper, -upper, 0.01, upper;  // upper, facing down
    body_F << 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7;
    body_next = body_t;
    body_next.bottomRows(4).col(1).array() -= 0.02;
    state.body.vertices = test::positions_tensor(body_t);
    state.body.next_vertices = test::positions_tensor(body_next);
    state.body.faces = test::faces_tensor(body_F);
  }
};

TEST(IntersectionFreeSolver, ClothPinchedByABodyClosingOnItselfIsReportedNotStuck) {
  // Plates as wide as the cloth: no intersection-free place is left while the upper plate
  // comes down. Not released, the plate is placed at its pose after its moves and the cloth it
  // then holds leaves barrier contact (and stays out, solver.readmit_at_rest off). With
  // solver.release_held_cloth the cloth that holds the plate back leaves contact as it comes
  // down, the plate gets to its pose (through the lower one), and there the cloth is pushed out
  // of both, above them, and rejoins barrier contact.
  PlatesClosingOnCloth scene(4, 0.5);
  const ClothGeometry& cloth = scene.cloth;
  FrameState& state = scene.state;
  for (const bool release : {false, true}) {
    SCOPED_TRACE(release ? "released" : "placed");
    PhysicsConfig config = barrier_config();
    config.solver.release_held_cloth = release;
    // Caught, the cloth would be pushed out above both plates where the solve stops, as the
    // released cloth is (ClothCaughtByThePlacedBodyRejoinsContactWhereTheSolveStops).
    config.solver.readmit_at_rest = release;
    const TermList terms = build_terms(state.effects, config);
    const SolverResult r = solve_reference_frame(state, cloth, terms, config);
    EXPECT_LE(r.iterations, config.solver.max_iterations);
    EXPECT_TRUE(torch::isfinite(r.x_next).all().item<bool>());
    if (!release) {
      EXPECT_GT(r.caught_by_body, 0);           // the cloth the plates close on leaves barrier contact...
      EXPECT_EQ(r.excluded, r.caught_by_body);  // ...and only that (the start was free)
      EXPECT_GT(r.body_lag, 0);                 // the body was placed at its pose, not reached
      EXPECT_LT(r.body_lag, 0.02 + 1e-12);
      EXPECT_EQ(r.released, 0);
    } else {
      EXPECT_GT(r.released, 0);  // the cloth the plates close on left barrier contact...
      EXPECT_EQ(r.body_lag, 0);  // ...the body reached its pose...
      EXPECT_EQ(r.excluded, 0);  // ...and all of it came back, free of the body
      const Freedom f = freedom(tensor_to_matrix(r.x_next), unique_edges(scene.g.F), scene.body_next, scene.body_F);
      EXPECT_GT(f.min_distance, 0);
      EXPECT_EQ(f.edges_through, 0);
    }
  }
}

// A sphere (r = 0.1 m) that moves 2 m in one step, to where a 10 cm patch of cloth lies (inside
// it there); its moves are 5 cm at most.
struct SphereMovingOntoAPatch {
  TriMesh patch = test::grid_mesh(5, 0.1);
  TriMesh sphere = test::icosphere(0.1, 3, Eigen::RowVector3d::Zero());
  Eigen::MatrixXd next;
  ClothGeometry cloth;
  FrameState state;
  SphereMovingOntoAPatch() {
    patch.V.col(0).array() += 2.0 - 0.05;
    patch.V.col(2).array() -= 0.05;
    patch.V.col(1).setConstant(0.05);
    cloth = make_cloth_geometry(patch);
    state = test::resting_state(test::positions_tensor(patch.V));
    state.effects.gravity = state.effects.collision = true;
    next = sphere.V;
    next.col(0).array() += 2.0;
    state.body.vertices = test::positions_tensor(sphere.V);
    state.body.next_vertices = test::positions_tensor(next);
    state.body.faces = test::faces_tensor(sphere.F);
  }
};

TEST(IntersectionFreeSolver, ABodyMovingFartherThanItsMovesCoverInOneGoGetsThereWithTheClothOutsideIt) {
  // 2 m takes 40 moves: with solver.release_held_cloth the body is allowed those and 24 more,
  // so it reaches its pose, the patch pushed out of its way (over it), and nothing is caught.
  SphereMovingOntoAPatch scene;
  PhysicsConfig config = barrier_config();
  config.solver.release_held_cloth = true;
  config.solver.barrier_keeps_penalty = false;
  const TermList terms = build_terms(scene.state.effects, config);
  const SolverResult r = solve_reference_frame(scene.state, scene.cloth, terms, config);
  EXPECT_EQ(r.body_lag, 0);
  EXPECT_EQ(r.caught_by_body, 0);
  ASSERT_TRUE(torch::isfinite(r.x_next).all().item<bool>());
  const Freedom f = freedom(tensor_to_matrix(r.x_next), unique_edges(scene.patch.F), scene.next, scene.sphere.F);
  EXPECT_GT(f.min_distance, 0);
  EXPECT_EQ(f.edges_through, 0);
}

TEST(IntersectionFreeSolver, BodyMovesTakenWholeCountTheirShareOfAFullMove) {
  // The hard cases' jump at the training edge, 72 frames: on frame 30 the body (341 mm to go)
  // made its way in moves of 1-16 mm, cut and grown again, and was placed 176 mm short with 335
  // vertices caught once it had made 31 of them, each counted as a whole 5 cm move.
  using namespace reference_solve;
  // Taken whole, the moves over a distance count that distance in full moves, whatever their size.
  double small = 0;
  for (int i = 0; i < 50; ++i) small += body_move_cost(1e-3, false);
  EXPECT_NEAR(small, 1e-3 * 50 / kMaxContactStep, 1e-12);
  EXPECT_DOUBLE_EQ(body_move_cost(kMaxContactStep, false), 1.0);
  // Cut: free while it can be tried again smaller; a whole move at the smallest size.
  EXPECT_EQ(body_move_cost(8e-3, true), 0.0);
  EXPECT_EQ(body_move_cost(kMinBodyMove, true), 1.0);
  // Never more than the count of before (every move 1, a cut one 0 only while it could shrink).
  for (const double size : {kMinBodyMove, 4e-3, kMaxContactStep})
    for (const bool cut : {false, true}) EXPECT_LE(body_move_cost(size, cut), 1.0);
}

TEST(IntersectionFreeSolver, ClothTheBodyIsPlacedOnIsPushedOutOfItWhereThereIsRoom) {
  // Given 10 iterations, the sphere's moves cannot get it there (0.5 m at most), so it is
  // placed at its pose onto the patch. Pushed out as a start is, none of the cloth is caught;
  // left as it is, all of it is.
  SphereMovingOntoAPatch scene;
  const TriMesh& patch = scene.patch;
  const TriMesh& sphere = scene.sphere;
  const Eigen::MatrixXd& next = scene.next;
  const ClothGeometry& cloth = scene.cloth;
  const FrameState& state = scene.state;
  const Eigen::MatrixXi edges = unique_edges(patch.F);
  for (const bool push : {true, false}) {
    SCOPED_TRACE(push ? "pushed out" : "left");
    PhysicsConfig config = barrier_config();
    config.solver.push_out_caught = push;
    config.solver.max_iterations = 10;
    config.solver.release_held_cloth = false;  // the body gets its 24 moves, then is placed
    // Without the penalty term, which measures the cloth against the body at its pose and would
    // move the patch out of the sphere's way before it arrives.
    config.solver.barrier_keeps_penalty = false;
    const TermList terms = build_terms(state.effects, config);
    const SolverResult r = solve_reference_frame(state, cloth, terms, config);
    EXPECT_GT(r.body_lag, 0.5);  // placed, not reached
    ASSERT_TRUE(torch::isfinite(r.x_next).all().item<bool>());
    const Freedom f = freedom(tensor_to_matrix(r.x_next), edges, next, sphere.F);
    if (push) {
      EXPECT_EQ(r.caught_by_body, 0);
      EXPECT_GT(f.min_distance, 0);
      EXPECT_EQ(f.edges_through, 0);
    } else {
      EXPECT_EQ(r.caught_by_body, patch.V.rows());
    }
  }
}

TEST(IntersectionFreeSolver, ClothCaughtByThePlacedBodyRejoinsContactWhereTheSolveStops) {
  // Not released, the sphere gets its 24 moves (1.2 m of the 2 m) and is placed at its pose onto
  // the patch, which is caught. The solve goes on and stops; with solver.readmit_at_rest the
  // whole patch is then pushed out of the sphere as a start is, rejoins barrier contact, and
  // the solve goes on to rest outside it. Without it the patch stays with the penalty term.
  SphereMovingOntoAPatch scene;
  const Eigen::MatrixXi edges = unique_edges(scene.patch.F);
  for (const bool readmit : {true, false}) {
    SCOPED_TRACE(readmit ? "readmitted" : "left out");
    PhysicsConfig config = barrier_config();
    config.solver.release_held_cloth = false;
    config.solver.barrier_keeps_penalty = false;
    config.solver.readmit_at_rest = readmit;
    const TermList terms = build_terms(scene.state.effects, config);
    const SolverResult r = solve_reference_frame(scene.state, scene.cloth, terms, config);
    EXPECT_GT(r.body_lag, 0.5);  // placed, not reached
    ASSERT_TRUE(torch::isfinite(r.x_next).all().item<bool>());
    if (readmit) {
      EXPECT_EQ(r.readmitted_at_rest, scene.patch.V.rows());
      EXPECT_EQ(r.excluded, 0);
      EXPECT_EQ(r.caught_by_body, 0);
      const Freedom f = freedom(tensor_to_matrix(r.x_next), edges, scene.next, scene.sphere.F);
      EXPECT_GT(f.min_distance, 0);
      EXPECT_EQ(f.edges_through, 0);
    } else {
      EXPECT_EQ(r.readmitted_at_rest, 0);
      EXPECT_EQ(r.caught_by_body, scene.patch.V.rows());
      EXPECT_EQ(r.excluded, r.caught_by_body);
    }
  }
}

TEST(RefinedStep, ReadsItsOwnReleaseOfTheClothThatHoldsTheBodyBack) {
  // The sphere moves 2 m onto the patch. The solver releases the cloth that holds it back by
  // default (physics.solver.release_held_cloth) and reaches its pose; a refinement reads its
  // own switch (refine.release_held_cloth, on by default too), whatever the solver's says: not
  // released, swept from the patch where it stands, its body gets 24 moves and is placed at its
  // pose, short of where the moves got it.
  SphereMovingOntoAPatch scene;
  PhysicsConfig config = barrier_config();
  ASSERT_TRUE(config.solver.release_held_cloth);
  ASSERT_TRUE(RefineConfig().release_held_cloth);
  config.solver.barrier_keeps_penalty = false;
  config.solver.given_start = "swept";
  const TermList terms = build_terms(scene.state.effects, config);
  const std::optional<BodyContact> contact = body_contact_for(scene.state, config);
  for (const bool release : {false, true}) {
    SCOPED_TRACE(release ? "released" : "not released");
    config.solver.release_held_cloth = !release;  // the solver's own switch is not the one read
    RefineConfig refine;
    refine.iterations = 10;
    refine.release_held_cloth = release;
    ContactStepLog log;
    const torch::Tensor x = refine_step(scene.state.x, scene.state, scene.cloth, terms, contact ? &*contact : nullptr,
                                        config.solver, refine, &log);
    ASSERT_TRUE(torch::isfinite(x).all().item<bool>());
    if (release) {
      EXPECT_EQ(log.body_lag, 0);
    } else {
      EXPECT_GT(log.body_lag, 0.5);  // placed, not reached
    }
  }
}

TEST(StepResidual, AStepThatLeftClothOutIsMeasuredWithTheSolversOwnExclusions) {
  // The plates above close on the cloth: the solver leaves the caught vertices out of barrier
  // contact and converges on the rest. Measured with the vertices it left out, its step is at
  // its tolerance; the set the residual would recompute from the step alone is another one (a
  // vertex next to one left inside ends an edge through the body), with another objective.
  PlatesClosingOnCloth scene(6, 0.02);  // a small upper plate
  const ClothGeometry& cloth = scene.cloth;
  FrameState& state = scene.state;
  PhysicsConfig config = barrier_config();
  config.solver.barrier_stiffness_max = 0;
  config.solver.max_iterations = 1000;
  const TermList terms = build_terms(state.effects, config);
  const std::optional<BodyContact> contact = body_contact_for(state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config.solver);
  ASSERT_TRUE(barrier.has_value());
  const SolverResult r = solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver, &*barrier);
  ASSERT_GT(r.excluded, 0);
  ASSERT_EQ(int64_t(r.excluded_vertices.size()), cloth.num_vertices);
  EXPECT_EQ(std::count(r.excluded_vertices.begin(), r.excluded_vertices.end(), 1), r.excluded);
  ASSERT_TRUE(r.converged) << r.step_norm;
  const BodyContact* c = contact ? &*contact : nullptr;
  const double own = step_residual(r.x_next, state, cloth, terms, c, &*barrier, &r.excluded_vertices);
  const double recomputed = step_residual(r.x_next, state, cloth, terms, c, &*barrier);
  std::printf("residual of a step that left %d vertices out: %.3g mm with its exclusions, %.3g mm recomputed\n",
              r.excluded, 1e3 * own, 1e3 * recomputed);
  EXPECT_LT(own, 1e-5);         // m
  EXPECT_GT(recomputed, 1e-4);  // what the residual read before it was given the solver's set
}

}  // namespace
}  // namespace pb4u
