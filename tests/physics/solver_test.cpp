// The reference solver (SPEC 8) on two small scenes: a cloth hanging from two pins, and a
// cloth dropped onto a sphere; its start where the prediction inverts a sliver; and its linear
// solve where rounding loses a pivot.
#include <gtest/gtest.h>

#include "pb4u/physics/elastic_solve.h"
#include "pb4u/physics/energy_report.h"
#include "pb4u/physics/reference_solver.h"
#include "pb4u/physics/step_residual.h"
#include "physics_test_util.h"
#include "test_util.h"

namespace pb4u {
namespace {

double kinetic_energy(const FrameState& s, const ClothGeometry& cloth) {
  return 0.5 * (cloth.vertex_masses(s.material.density) * s.velocity().pow(2).sum(1)).sum().item<double>();
}

// Advances `state` by one solved frame; returns the solve.
SolverResult step(FrameState& state, const ClothGeometry& cloth, const TermList& terms,
                  const PhysicsConfig& config) {
  SolverResult r = solve_reference_frame(state, cloth, terms, config);
  state.x_prev = state.x;
  state.x = r.x_next;
  return r;
}

// The residual's step from a cloth over a sphere, one solved frame in, and moved off that
// frame's output. gap: the cloth's start above the sphere's top (m).
struct SolvedOverSphere {
  TriMesh g;
  FrameState state;
  ClothGeometry cloth;
  PhysicsConfig config;
  TermList terms;
  std::optional<BodyContact> contact;
  SolverResult r;
  explicit SolvedOverSphere(double gap) {
    state = test::cloth_above_sphere(6, 0.3, 0.25, gap, 3, &g);
    cloth = make_cloth_geometry(g);
    config.solver.max_iterations = 1000;
    terms = build_terms(state.effects, config);
    contact = body_contact_for(state, config);
    r = solve_reference_frame(state, cloth, terms, config);
  }
  // mm
  double residual(const torch::Tensor& x, ResidualHessian h = ResidualHessian::newton) const {
    return 1e3 * step_residual(x, state, cloth, terms, contact ? &*contact : nullptr, nullptr, nullptr, h);
  }
};

TEST(StepResidual, IsTheSolversStoppingStepAtItsSolutionAndAnOffsetsLengthAwayFromIt) {
  // gap 1 cm: the cloth falls into the penalty term's reach within the frame.
  const SolvedOverSphere touching(0.01);
  ASSERT_TRUE(touching.r.converged);
  // Per vertex (the solver's step norm is per coordinate): at most sqrt(3) x its tolerance.
  const double tolerance_mm = 1e3 * std::sqrt(3.0) * touching.config.solver.step_tolerance;
  EXPECT_LT(touching.residual(touching.r.x_next), tolerance_mm);
  EXPECT_LT(touching.residual(touching.r.x_next, ResidualHessian::quasi_newton), tolerance_mm);

  // gap 10 cm: the cloth falls in the air, where the energy is smooth and the Newton step
  // reads an offset's length. Every vertex 1 mm up; one interior vertex 1 mm out of the
  // cloth's plane (a wrinkle), which the isotropic metric's membrane stiffness reads short.
  const SolvedOverSphere falling(0.1);
  ASSERT_TRUE(falling.r.converged);
  const torch::Tensor up = torch::tensor({0.0, 1e-3, 0.0}, torch::kFloat64);
  const double lifted = falling.residual(falling.r.x_next + up);
  torch::Tensor wrinkled = falling.r.x_next.clone();
  wrinkled[24][1] += 1e-3;  // the 7 x 7 grid's middle vertex
  const double wrinkle = falling.residual(wrinkled);
  const double wrinkle_isotropic = falling.residual(wrinkled, ResidualHessian::quasi_newton);
  std::printf("in the air, lifted 1 mm: %.3g mm; one vertex 1 mm out of the plane: %.3g mm (isotropic metric %.3g mm)\n",
              lifted, wrinkle, wrinkle_isotropic);
  EXPECT_NEAR(lifted, 1.0, 0.05);
  EXPECT_GT(wrinkle, 0.5);
  EXPECT_LT(wrinkle, 2.0);
  EXPECT_LT(wrinkle_isotropic, 0.1);

  // Touching, every vertex 1 mm up: the step from there no longer sees the contact's curvature
  // that holds the cloth at the minimum, so it reads long, but no farther than the offset plus
  // a frame's free fall (g dt^2, 10.9 mm at 30 fps).
  const double off_contact = touching.residual(touching.r.x_next + up);
  std::printf("touching, lifted 1 mm: %.3g mm\n", off_contact);
  EXPECT_GT(off_contact, 0.5);
  EXPECT_LT(off_contact, 1.0 + 1e3 * 9.81 * touching.state.dt * touching.state.dt);
}

// A face flattened to a sliver: the bending's gradient grows as 1 / the face's height, and the
// residual's H carries its curvature (growing as 1 / height^2), so the step still reads as a
// distance: here about how far the vertex is from its rest place, the energy's minimum. Without
// that curvature this state read 223 m (and a face at 2.6e-7 of its rest area on the hard
// cases' jump 2.5e6 mm).
TEST(StepResidual, AFaceFlattenedToASliverReadsADistanceNotKilometres) {
  TriMesh g = test::grid_mesh(4, 0.4);  // 0.1 m cells
  const ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  PhysicsConfig config;
  const TermList terms = build_terms(state.effects, config);
  // Vertex 12 (interior) 1 nm from the edge 7-11 opposite it in face (7, 11, 12), 71 mm from
  // its rest place, turned 60 degrees out of the cloth's plane: that face at ~1e-8 of its rest
  // area, its hinge with (6, 11, 7) folded by 60 degrees.
  const Eigen::RowVector3d a = g.V.row(7), b = g.V.row(11);
  Eigen::RowVector3d toward = g.V.row(12) - 0.5 * (a + b);
  const double from_rest = toward.norm();
  toward.normalize();
  const Eigen::RowVector3d up(0, 1, 0);
  Eigen::MatrixXd X = g.V;
  X.row(12) = 0.5 * (a + b) + 1e-9 * (0.5 * toward + std::sqrt(0.75) * up);
  const double residual = step_residual(test::positions_tensor(X), state, cloth, terms, nullptr);
  EXPECT_TRUE(std::isfinite(residual));
  EXPECT_GT(residual, 0.2 * from_rest);  // far from the minimum, and it says so
  EXPECT_LT(residual, 3 * from_rest);    // 99 mm here; 223 m without the bending's curvature
}

TEST(ReferenceSolver, PinnedClothSettlesIntoADrapeBelowThePins) {
  const int n = 6;
  TriMesh g = test::grid_mesh(n, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  state.effects.gravity = state.effects.pins = true;
  state.pinned = torch::zeros({cloth.num_vertices}, torch::kBool);
  state.pinned[0] = true;
  state.pinned[n] = true;  // the two corners of one side
  state.pin_targets = state.x.clone();
  PhysicsConfig config;
  TermList terms = build_terms(state.effects, config);

  std::vector<double> kinetic;
  SolverResult last;
  for (int frame = 0; frame < 60; ++frame) {
    last = step(state, cloth, terms, config);
    kinetic.push_back(kinetic_energy(state, cloth));
  }
  double peak = *std::max_element(kinetic.begin(), kinetic.end());
  EXPECT_GT(peak, 0.0);
  EXPECT_LT(kinetic.back(), 0.05 * peak) << "kinetic energy did not decay";
  EXPECT_TRUE(last.converged) << "step " << last.step_norm << " m";
  EXPECT_LE(last.step_norm, config.solver.step_tolerance);
  // The drape is an energy minimum: the residual force is tiny next to a vertex's weight.
  double weight = (cloth.vertex_masses(state.material.density).min() * 9.81).item<double>();
  EXPECT_LT(last.gradient_norm, 1e-2 * weight);
  // Pins held exactly; everything else hangs below them.
  EXPECT_TRUE(torch::equal(state.x[0], state.pin_targets[0]));
  EXPECT_TRUE(torch::equal(state.x[n], state.pin_targets[n]));
  double lowest = state.x.select(1, 1).min().item<double>();
  EXPECT_LT(lowest, -0.3) << "the cloth should hang about its length (0.5 m) below the pins";
  EXPECT_GT(lowest, -0.6) << "stretched far beyond its length";
}

TEST(ReferenceSolver, ExtremeTrainingMaterialsStayFiniteAndBounded) {
  // The stiffest, lightest corner of the training ranges (SPEC 2), hanging from two pins.
  const int n = 5;
  TriMesh g = test::grid_mesh(n, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  for (double density : {0.0434, 0.7}) {
    FrameState state = test::resting_state(test::positions_tensor(g.V));
    state.material.density = density;
    state.material.mu = 63636;
    state.material.lambda = 93333.74;
    state.material.bending = 1.3139738e-3;
    state.effects.gravity = state.effects.pins = true;
    state.pinned = torch::zeros({cloth.num_vertices}, torch::kBool);
    state.pinned[0] = state.pinned[n] = true;
    state.pin_targets = state.x.clone();
    PhysicsConfig config;
    config.solver.max_iterations = 50;  // a tight budget must still give a sane state
    TermList terms = build_terms(state.effects, config);
    for (int frame = 0; frame < 10; ++frame) step(state, cloth, terms, config);
    EXPECT_TRUE(torch::isfinite(state.x).all().item<bool>()) << density;
    // Bounded: nothing leaves the sphere of the cloth's size around the pins.
    EXPECT_LT((state.x - state.pin_targets[0]).norm(2, 1).max().item<double>(), 1.0) << density;
  }
}

TEST(ReferenceSolver, FrictionCarriesAClothOnAMovingFloor) {
  TriMesh floor = test::grid_mesh(2, 4.0);
  floor.V.col(0).array() -= 2.0;
  floor.V.col(2).array() -= 2.0;
  TriMesh g = test::grid_mesh(3, 0.2);
  g.V.col(1).array() += 1.5e-3;  // resting inside the contact band
  ClothGeometry cloth = make_cloth_geometry(g);
  const double speed = 0.01;  // m per frame along x
  const int frames = 10;
  auto carried = [&](bool friction) {
    FrameState state = test::resting_state(test::positions_tensor(g.V));
    state.effects.gravity = state.effects.collision = true;
    state.effects.friction = friction;
    state.body = test::static_body(floor);
    PhysicsConfig config;
    TermList terms = build_terms(state.effects, config);
    torch::Tensor shift = torch::tensor({speed, 0.0, 0.0}, torch::kFloat64);
    for (int f = 0; f < frames; ++f) {
      state.body.vertices = test::positions_tensor(floor.V) + f * shift;
      state.body.next_vertices = state.body.vertices + shift;
      step(state, cloth, terms, config);
    }
    return (state.x - test::positions_tensor(g.V)).select(1, 0).mean().item<double>();
  };
  EXPECT_GT(carried(true), 0.5 * speed * frames);
  EXPECT_LT(std::abs(carried(false)), 0.05 * speed * frames);
}

TEST(ReferenceSolver, HonoursEffectsWithoutGravityARestingClothStaysPut) {
  TriMesh g = test::grid_mesh(4, 0.5);
  ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));  // no effects at all
  PhysicsConfig config;
  TermList terms = build_terms(state.effects, config);
  SolverResult r = solve_reference_step(state, cloth, terms, nullptr, config.solver);
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_TRUE(torch::allclose(r.x_next, state.x, 0.0, 1e-12));
  // The same cloth with gravity on does move (down).
  state.effects.gravity = true;
  r = solve_reference_step(state, cloth, build_terms(state.effects, config), nullptr, config.solver);
  EXPECT_LT((r.x_next - state.x).select(1, 1).max().item<double>(), -1e-3);
}

TEST(ReferenceSolver, ClothDroppedOnASphereRestsOnItWithoutPenetratingDeeperThanEps) {
  const double radius = 0.25;
  TriMesh g;
  FrameState state = test::cloth_above_sphere(6, 0.3, radius, 0.01, 3, &g);
  ClothGeometry cloth = make_cloth_geometry(g);
  PhysicsConfig config;
  TermList terms = build_terms(state.effects, config);
  for (int frame = 0; frame < 20; ++frame) step(state, cloth, terms, config);

  // Measured against the body's faces as the terms see them, at the final positions.
  BodyContact c = query_body_contact(state.x, state.body, config.friction.contact_radius,
                                     config.degenerate_area);
  EXPECT_GT(c.distance.min().item<double>(), -config.collision.eps);
  EXPECT_TRUE(c.in_contact.any().item<bool>()) << "the cloth should touch the sphere";
  // Resting on top: the centre vertex is just above the sphere's pole, not fallen through.
  double centre_y = state.x[24][1].item<double>();
  EXPECT_GT(centre_y, radius - config.collision.eps);
  EXPECT_LT(centre_y, radius + 0.01);
  EXPECT_LT(kinetic_energy(state, cloth), 1e-3);
}

TEST(ReferenceSolver, APredictionThatInvertsASliverStartsFromTheClothWhereItStands) {
  // A cloth of 28 x 8 vertices hanging in the xy plane from its top row, 4 cm between
  // neighbours, but rows 2 and 3 1e-8 m apart: a strip of slivers (as HardCases.SliverTriangles
  // at scale 4, where the prediction blew the solve up to 759 J). Row 3 moved 1 um up in the last
  // frame, so the ballistic prediction puts it above row 2: every sliver inverted, and bending's
  // hinges beside them (weighted by 1 / area) jump to over 1 J. Standing still costs only that
  // 1 um's kinetic energy. The solve starts from the lower.
  const int n = 28;
  const TriMesh g = test::lattice_cloth(n, 8, 0.04, 2, 1e-8);
  const ClothGeometry cloth = make_cloth_geometry(g);
  FrameState state = test::resting_state(test::positions_tensor(g.V));
  state.effects.gravity = state.effects.pins = true;
  state.pinned = torch::zeros({cloth.num_vertices}, torch::kBool);
  state.pinned.slice(0, 0, n) = true;
  state.pin_targets = state.x.clone();
  state.x_prev.slice(0, 3 * n, 4 * n).select(1, 1) -= 1e-6;
  PhysicsConfig config;
  const TermList terms = build_terms(state.effects, config);
  const torch::Tensor predicted = 2 * state.x - state.x_prev;
  ASSERT_GT(positive_energy(energy_report(terms, predicted, state, cloth, nullptr)), 1.0);

  const SolverResult r = solve_reference_frame(state, cloth, terms, config);
  EXPECT_TRUE(r.standing_start);
  ASSERT_TRUE(torch::isfinite(r.x_next).all().item<bool>());
  // The step's objective is no higher than standing still's, so its elastic energy is bounded
  // by what the cloth held at t plus that kinetic energy, converged or not (from the prediction
  // the solve ends at 0.067 J).
  const EnergyReport standing = energy_report(terms, state.x, state, cloth, nullptr);
  const EnergyReport solved = energy_report(terms, r.x_next, state, cloth, nullptr);
  EXPECT_LE(solved.total, standing.total);
  EXPECT_LT(positive_energy(solved), 1e-3) << "standing still: " << positive_energy(standing) << " J";
}

TEST(ElasticSolve, APivotLostToRoundingIsFactorisedWithAShiftedDiagonal) {
  // [[1, 1], [1, 1]] is positive semi-definite, but its LDL^T meets a zero pivot, as a Newton
  // Hessian with 1e19 entries beside 1e2 ones does after rounding: the solve shifts the
  // diagonal and goes on.
  ElasticSolve e;
  e.base.resize(2, 2);
  std::vector<Eigen::Triplet<double>> t{{0, 0, 1.0}, {0, 1, 1.0}, {1, 0, 1.0}, {1, 1, 1.0}};
  e.base.setFromTriplets(t.begin(), t.end());
  e.ldlt.analyzePattern(e.base);  // as quasi_newton_elastic_solve does, once
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> plain(e.base);
  ASSERT_NE(plain.info(), Eigen::Success);
  ASSERT_NO_THROW(e.factorize(torch::Tensor()));
  const torch::Tensor x = e(torch::tensor({1.0, 0.0, 0.0, 1.0, 0.0, 0.0}, torch::kFloat64));
  // (1, 1) lies in the matrix's range: the shifted solve returns its solution (0.5, 0.5) there.
  const std::vector<double> expected{0.5, 0, 0, 0.5, 0, 0};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(x[i].item<double>(), expected[size_t(i)], 1e-9);
}

}  // namespace
}  // namespace pb4u
