// Strain limiting as a barrier: its derivatives against finite differences, the step filter
// against the closed form for one edge, and the solver keeping a soft, heavy pinned cloth's
// edges under the limit that its StVK stretch alone lets it pass.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pb4u/mesh/edges.h"
#include "pb4u/physics/penetration.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/physics/strain_barrier.h"
#include "pb4u/util/eigen_tensor.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

Eigen::VectorXd rest_lengths(const Eigen::MatrixXd& V, const Eigen::MatrixXi& E) {
  Eigen::VectorXd L(E.rows());
  for (Eigen::Index e = 0; e < E.rows(); ++e) L(e) = (V.row(E(e, 0)) - V.row(E(e, 1))).norm();
  return L;
}

TEST(StrainBarrier, GradientAndCurvatureAreTheEnergysDerivatives) {
  const TriMesh g = test::grid_mesh(3, 0.3);
  const Eigen::MatrixXi E = unique_edges(g.F);
  const Eigen::VectorXd L = rest_lengths(g.V, E);
  // Stretched 9.5% in x with a little noise: the x edges sit in the barrier's band (9%-10%).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-2e-5, 2e-5);
  Eigen::MatrixXd x = g.V;
  x.col(0) *= 1.095;
  for (Eigen::Index i = 0; i < x.size(); ++i) x.data()[i] += noise(rng);
  const StrainBarrierSettings s{0.1, 0.01, 2.0};
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(x.rows(), 3);
  const StrainBarrierValue v = strain_barrier(x, E, L, s, {}, &G);
  ASSERT_GT(v.active, 0);
  ASSERT_GT(v.energy, 0);
  const double h = 1e-7;
  for (Eigen::Index i = 0; i < x.rows(); ++i)
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd up = x, down = x;
      up(i, c) += h;
      down(i, c) -= h;
      const double fd = (strain_barrier(up, E, L, s, {}).energy - strain_barrier(down, E, L, s, {}).energy) / (2 * h);
      EXPECT_NEAR(G(i, c), fd, 1e-5 * std::max(1.0, std::abs(fd))) << i << " " << c;
    }
  // One edge alone, its end moved along the edge: the curvature is d2E/dx2 exactly.
  Eigen::MatrixXd two(2, 3);
  two << 0, 0, 0, 1.095, 0, 0;
  const Eigen::MatrixXi e01 = (Eigen::MatrixXi(1, 2) << 0, 1).finished();
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(1);
  Eigen::VectorXd curvature = Eigen::VectorXd::Zero(2);
  const double e0 = strain_barrier(two, e01, one, s, {}, nullptr, &curvature).energy;
  Eigen::MatrixXd plus = two, minus = two;
  plus(1, 0) += 1e-5;
  minus(1, 0) -= 1e-5;
  const double fd2 = (strain_barrier(plus, e01, one, s, {}).energy - 2 * e0 + strain_barrier(minus, e01, one, s, {}).energy) / 1e-10;
  EXPECT_NEAR(curvature(1), fd2, 1e-3 * fd2);
  // Past the limit it is infinite, unless the edge is left out; far from it, zero.
  two(1, 0) = 1.1;
  EXPECT_TRUE(std::isinf(strain_barrier(two, e01, one, s, {}).energy));
  EXPECT_EQ(strain_barrier(two, e01, one, s, {1}).energy, 0.0);
  two(1, 0) = 1.05;
  EXPECT_EQ(strain_barrier(two, e01, one, s, {}).energy, 0.0);
}

TEST(StrainBarrier, TheStepStopsShortOfTheLimitAsTheClosedFormSays) {
  Eigen::MatrixXd x(2, 3), dx(2, 3);
  x << 0, 0, 0, 1.05, 0, 0;  // rest 1: 5% strain
  dx << 0, 0, 0, 0.1, 0, 0;  // would reach 10% at half the step
  const Eigen::MatrixXi e01 = (Eigen::MatrixXi(1, 2) << 0, 1).finished();
  const Eigen::VectorXd one = Eigen::VectorXd::Ones(1);
  EXPECT_NEAR(max_strain_step(x, dx, e01, one, 0.1, {}), 0.8 * 0.5, 1e-12);
  // Sideways: |(1.05, 0.4 a, 0)| = 1.1 at a = sqrt(1.1^2 - 1.05^2) / 0.4.
  dx << 0, 0, 0, 0, 0.4, 0;
  EXPECT_NEAR(max_strain_step(x, dx, e01, one, 0.1, {}), 0.8 * std::sqrt(1.21 - 1.1025) / 0.4, 1e-12);
  dx << 0, 0, 0, -0.3, 0, 0;  // shortening: the whole step
  EXPECT_EQ(max_strain_step(x, dx, e01, one, 0.1, {}), 1.0);
  dx << 0, 0, 0, 0.1, 0, 0;
  EXPECT_EQ(max_strain_step(x, dx, e01, one, 0.1, {1}), 1.0);  // left out
  // Provot's start: an edge at 30% shortened to the limit, the pinned end kept.
  x << 0, 0, 0, 1.3, 0, 0;
  const Eigen::MatrixXd y = shorten_overstretched_edges(x, e01, one, 0.1, {1, 0});
  EXPECT_EQ(y.row(0), x.row(0));
  EXPECT_NEAR(y(1, 0), 1.1, 1e-12);
  EXPECT_EQ(edges_over_strain(x, e01, one, 0.1), std::vector<char>{1});
}

// A soft, heavy square cloth hanging from one pinned side: StVK alone lets its edges stretch
// well past 10%; with solver.strain_limit 0.1 none passes it, and the limit is reached.
TEST(StrainBarrier, TheSolverKeepsASoftHeavyClothUnderTheLimit) {
  const int n = 4;
  const TriMesh g = test::grid_mesh(n, 0.4);
  const ClothGeometry cloth = make_cloth_geometry(g);
  const Eigen::MatrixXi E = unique_edges(g.F);
  const Eigen::VectorXd L = rest_lengths(g.V, E);
  auto hang = [&](double limit, double* max_strain, int* excluded) {
    FrameState state = test::resting_state(test::positions_tensor(g.V));
    state.material.mu = 20;
    state.material.lambda = 20;
    state.material.density = 1.0;
    state.effects.gravity = state.effects.pins = true;
    state.pinned = torch::zeros({cloth.num_vertices}, torch::kBool);
    for (int j = 0; j <= n; ++j) state.pinned[j] = true;  // the side z = 0
    state.pin_targets = state.x.clone();
    PhysicsConfig config;
    config.solver.strain_limit = limit;
    config.solver.max_iterations = 400;
    const TermList terms = build_terms(state.effects, config);
    *excluded = 0;
    for (int frame = 0; frame < 30; ++frame) {
      const SolverResult r = solve_reference_frame(state, cloth, terms, config);
      *excluded += r.strain_excluded;
      state.x_prev = state.x;
      state.x = r.x_next;
    }
    const Eigen::MatrixXd X = tensor_to_matrix(state.x);
    *max_strain = 0;
    for (Eigen::Index e = 0; e < E.rows(); ++e)
      *max_strain = std::max(*max_strain, (X.row(E(e, 0)) - X.row(E(e, 1))).norm() / L(e) - 1);
  };
  double free_strain = 0, limited_strain = 0;
  int free_excluded = 0, limited_excluded = 0;
  hang(0, &free_strain, &free_excluded);
  ASSERT_GT(free_strain, 0.2) << "the test cloth must stretch past the limit without it";
  hang(0.1, &limited_strain, &limited_excluded);
  EXPECT_LE(limited_strain, 0.1);
  EXPECT_GT(limited_strain, 0.09) << "the barrier holds the cloth at its limit";
  EXPECT_EQ(limited_excluded, 0);
}

// A refined network step that is both inside the body and overstretched (30%): a start that
// alternates Provot's pass and the push out of the body, then 5 iterations, leave it free of
// the body and within the limit, with nothing left out of either barrier.
TEST(StrainBarrier, ARefinedStepInsideTheBodyAndOverstretchedEndsFreeAndWithinTheLimit) {
  TriMesh g;
  FrameState state = test::cloth_above_sphere(6, 0.3, 0.25, 0.002, 3, &g);
  const ClothGeometry cloth = make_cloth_geometry(g);
  const Eigen::MatrixXi E = unique_edges(g.F);
  const Eigen::VectorXd L = rest_lengths(g.V, E);
  Eigen::MatrixXd bad = tensor_to_matrix(state.x);
  const Eigen::RowVector3d centre = bad.colwise().mean();
  for (Eigen::Index i = 0; i < bad.rows(); ++i) {
    bad(i, 0) = centre(0) + 1.3 * (bad(i, 0) - centre(0));
    bad(i, 2) = centre(2) + 1.3 * (bad(i, 2) - centre(2));
    bad(i, 1) -= 0.01;  // 8 mm into the sphere at its top
  }
  ASSERT_GT(garment_penetration(bad, tensor_to_matrix(state.body.next_vertices), index_tensor_to_matrix(state.body.faces))
                .penetrating_fraction, 0.0);
  PhysicsConfig config;
  config.solver.contact = "barrier";
  config.solver.strain_limit = 0.1;
  config.solver.max_iterations = 5;
  const TermList terms = build_terms(state.effects, config);
  const std::optional<BodyContact> contact = body_contact_for(state, config);
  const std::optional<BarrierStepInput> barrier = barrier_step_input(state, cloth, config.solver);
  ASSERT_TRUE(barrier.has_value());
  const torch::Tensor start = matrix_to_tensor(bad);
  const SolverResult r = solve_reference_step(state, cloth, terms, contact ? &*contact : nullptr, config.solver, &*barrier, &start);
  const Eigen::MatrixXd X = tensor_to_matrix(r.x_next);
  EXPECT_EQ(r.excluded, 0);
  EXPECT_EQ(r.strain_excluded, 0);
  double max_strain = 0;
  for (Eigen::Index e = 0; e < E.rows(); ++e) max_strain = std::max(max_strain, (X.row(E(e, 0)) - X.row(E(e, 1))).norm() / L(e) - 1);
  EXPECT_LE(max_strain, 0.1);
  const ContactSurface body = make_contact_surface(barrier->body_next, barrier->body_faces);
  EXPECT_TRUE(cloth_edges_through_body(X, barrier->cloth_edges, body).empty());
  EXPECT_EQ(garment_penetration(X, barrier->body_next, barrier->body_faces).penetrating_fraction, 0.0);
}

}  // namespace
}  // namespace pb4u
